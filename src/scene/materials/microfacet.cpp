#include "src/scene/materials/microfacet.h"

#include "emlt/core/warp.h"

namespace emlt {

namespace {
Vec3 upper(const Vec3& w) { return w.z < 0.0f ? -w : w; }

// Mitsuba zeroes D where D(m) m.z < 1e-20 ("numerical issues in other stages"); kept so
// that the far tails agree with it, and so that sampled normals there are simply lost.
constexpr float kMinProjectedDensity = 1e-20f;
}  // namespace

MicrofacetDistribution::MicrofacetDistribution(MicrofacetType type, float alpha_u, float alpha_v)
    : type_(type), alpha_u_(glm::max(alpha_u, kMinAlpha)), alpha_v_(glm::max(alpha_v, kMinAlpha)) {
  if (type_ == MicrofacetType::Phong) {
    // Walter et al.'s Beckmann-equivalent exponent, as Mitsuba converts alpha.
    exponent_u_ = glm::max(2.0f / (alpha_u_ * alpha_u_) - 2.0f, 0.0f);
    exponent_v_ = glm::max(2.0f / (alpha_v_ * alpha_v_) - 2.0f, 0.0f);
  }
}

float MicrofacetDistribution::D(const Vec3& m) const {
  if (m.z <= 0.0f) return 0.0f;
  const float z2 = m.z * m.z;
  float d = 0.0f;
  switch (type_) {
    case MicrofacetType::Ggx: {
      // 1 / (pi au av cos^4 (1 + tan^2 (cos^2 phi / au^2 + sin^2 phi / av^2))^2), without
      // tan so that it stays finite at grazing m.
      const float s = m.x * m.x / (alpha_u_ * alpha_u_) + m.y * m.y / (alpha_v_ * alpha_v_) + z2;
      d = 1.0f / (kPi * alpha_u_ * alpha_v_ * s * s);
      break;
    }
    case MicrofacetType::Beckmann: {
      const float exponent =
          (m.x * m.x / (alpha_u_ * alpha_u_) + m.y * m.y / (alpha_v_ * alpha_v_)) / z2;
      // exp(-x) / cos^4 is zero well before either part underflows (which would give 0 / 0).
      if (!(exponent < 80.0f)) return 0.0f;
      d = std::exp(-exponent) / (kPi * alpha_u_ * alpha_v_ * z2 * z2);
      break;
    }
    case MicrofacetType::Phong: {
      // Ashikhmin-Shirley: the exponent interpolated over the azimuth of m; Phong when
      // isotropic. Normalised by sqrt((eu + 2)(ev + 2)) / (2 pi).
      const float sin2 = m.x * m.x + m.y * m.y;
      const float exponent = isotropic() || !(sin2 > 1e-30f)
                                 ? exponent_u_
                                 : (exponent_u_ * m.x * m.x + exponent_v_ * m.y * m.y) / sin2;
      d = std::sqrt((exponent_u_ + 2.0f) * (exponent_v_ + 2.0f)) * kInvTwoPi *
          std::pow(m.z, exponent);
      break;
    }
  }
  return d * m.z < kMinProjectedDensity ? 0.0f : d;
}

float MicrofacetDistribution::lambda(const Vec3& w) const {
  const float p = projected_alpha2_sin2(w);  // alpha(phi)^2 sin^2 theta
  if (p == 0.0f) return 0.0f;
  if (w.z == 0.0f) return kInfinity;
  if (type_ == MicrofacetType::Ggx) return 0.5f * (std::sqrt(1.0f + p / (w.z * w.z)) - 1.0f);
  const float a = std::abs(w.z) / std::sqrt(p);  // 1 / (alpha(phi) tan theta)
  return 0.5f * (std::erf(a) - 1.0f) + std::exp(-a * a) / (2.0f * a * std::sqrt(kPi));
}

float MicrofacetDistribution::G1(const Vec3& w, const Vec3& m) const {
  // A direction cannot see the back of a microfacet, nor one from below the surface.
  if (glm::dot(w, m) * w.z <= 0.0f) return 0.0f;
  const float p = projected_alpha2_sin2(w);
  if (p == 0.0f) return 1.0f;  // normal incidence: nothing masks
  if (type_ == MicrofacetType::Ggx) return 2.0f / (1.0f + std::sqrt(1.0f + p / (w.z * w.z)));
  // Beckmann and Phong: Walter et al. 2007's rational approximation, as Mitsuba uses.
  const float a = std::abs(w.z) / std::sqrt(p);
  if (a >= 1.6f) return 1.0f;
  return (3.535f * a + 2.181f * a * a) / (1.0f + 2.276f * a + 2.577f * a * a);
}

Vec3 MicrofacetDistribution::sample_ggx_visible(const Vec3& wo, const Vec2& u) const {
  // Stretch to the configuration where the microsurface is a hemisphere of radius 1,
  // sample the visible part of its projected disk, and unstretch (Heitz 2018; the stretch
  // by alpha_u, alpha_v along s, t makes it exact for the anisotropic distribution too).
  const Vec3 v = glm::normalize(Vec3(alpha_u_ * wo.x, alpha_v_ * wo.y, wo.z));
  const float len2 = v.x * v.x + v.y * v.y;
  const Vec3 t1 = len2 > 0.0f ? Vec3(-v.y, v.x, 0.0f) / std::sqrt(len2) : Vec3(1, 0, 0);
  const Vec3 t2 = glm::cross(v, t1);
  // Uniform point on the unit disk, then warp the lower half onto the part of the
  // projected hemisphere that faces v (it shrinks to a half-ellipse at grazing v).
  const float r = std::sqrt(u.x);
  const Vec2 circle = unit_circle_point(u.y);
  const float p1 = r * circle.x;
  float p2 = r * circle.y;
  const float s = 0.5f * (1.0f + v.z);
  p2 = (1.0f - s) * safe_sqrt(1.0f - p1 * p1) + s * p2;
  const Vec3 n_h = p1 * t1 + p2 * t2 + safe_sqrt(1.0f - p1 * p1 - p2 * p2) * v;
  return glm::normalize(Vec3(alpha_u_ * n_h.x, alpha_v_ * n_h.y, glm::max(n_h.z, 1e-7f)));
}

Vec3 MicrofacetDistribution::sample_beckmann(const Vec2& u) const {
  // The slopes of an anisotropic Beckmann surface are Gaussian, independent along s and t
  // with variances alpha_u^2 / 2 and alpha_v^2 / 2: Box-Muller. The normal of slope
  // (x, y) is (-x, -y, 1) normalised; the sign is immaterial (the Gaussian is symmetric).
  const float r = std::sqrt(-std::log1p(-glm::min(u.x, kOneMinusEpsilon)));
  const Vec2 circle = unit_circle_point(u.y);
  return glm::normalize(Vec3(alpha_u_ * r * circle.x, alpha_v_ * r * circle.y, 1.0f));
}

Vec3 MicrofacetDistribution::sample_phong(const Vec2& u) const {
  float phi = kTwoPi * u.y;
  float exponent = exponent_u_;
  if (!isotropic()) {
    // The azimuth's marginal is sqrt(AB) / (2 pi (A cos^2 + B sin^2)), A = eu + 2,
    // B = ev + 2, whose cdf over a quadrant inverts to atan(sqrt(A / B) tan(pi u / 2)).
    // Each quadrant takes a quarter of u.y, mirrored so that the map stays continuous.
    const auto first_quadrant = [&](float u1) {
      return std::atan(std::sqrt((exponent_u_ + 2.0f) / (exponent_v_ + 2.0f)) *
                       std::tan(0.5f * kPi * u1));
    };
    if (u.y < 0.25f)
      phi = first_quadrant(4.0f * u.y);
    else if (u.y < 0.5f)
      phi = kPi - first_quadrant(4.0f * (0.5f - u.y));
    else if (u.y < 0.75f)
      phi = kPi + first_quadrant(4.0f * (u.y - 0.5f));
    else
      phi = kTwoPi - first_quadrant(4.0f * (1.0f - u.y));
    const float c = std::cos(phi), s = std::sin(phi);
    exponent = exponent_u_ * c * c + exponent_v_ * s * s;
  }
  // Given the azimuth, cos theta has density (e + 2) cos^(e + 1) per d(cos theta).
  const float cos_theta = std::pow(u.x, 1.0f / (exponent + 2.0f));
  const float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

Vec3 MicrofacetDistribution::sample_normal(const Vec3& wo, const Vec2& u) const {
  switch (type_) {
    case MicrofacetType::Ggx: return sample_ggx_visible(upper(wo), u);
    case MicrofacetType::Beckmann: return sample_beckmann(u);
    case MicrofacetType::Phong: break;
  }
  return sample_phong(u);
}

float MicrofacetDistribution::normal_pdf(const Vec3& wo, const Vec3& m) const {
  if (type_ != MicrofacetType::Ggx) return D(m) * glm::max(m.z, 0.0f);
  const Vec3 w = upper(wo);
  if (w.z <= 0.0f) return 0.0f;
  const float wo_dot_m = glm::dot(w, m);
  if (wo_dot_m <= 0.0f) return 0.0f;
  // The visible normals' normalisation is exactly the Smith G1 = 1 / (1 + Lambda).
  return wo_dot_m * D(m) / ((1.0f + lambda(w)) * w.z);
}

float MicrofacetDistribution::reflection_pdf(const Vec3& wo, const Vec3& wi) const {
  if (wo.z * wi.z <= 0.0f) return 0.0f;
  const Vec3 h = reflection_half_vector(upper(wo), upper(wi));
  const float wo_dot_h = glm::dot(upper(wo), h);
  if (wo_dot_h <= 0.0f) return 0.0f;
  return normal_pdf(wo, h) / (4.0f * wo_dot_h);
}

}  // namespace emlt
