#include "src/scene/materials/microfacet.h"

namespace emlt {

float GgxDistribution::D(const Vec3& m) const {
  if (m.z <= 0.0f) return 0.0f;
  // D = 1 / (pi a^2 cos^4 (1 + tan^2 / a^2)^2), rewritten without tan so that it stays
  // finite at grazing m: cos^2 (1 + tan^2/a^2) = z^2 + (x^2 + y^2) / a^2.
  const float a2 = alpha_ * alpha_;
  const float s = (m.x * m.x + m.y * m.y) / a2 + m.z * m.z;
  return 1.0f / (kPi * a2 * s * s);
}

float GgxDistribution::lambda(const Vec3& w) const {
  const float z2 = w.z * w.z;
  if (z2 <= 0.0f) return kInfinity;
  const float alpha2_tan2 = alpha_ * alpha_ * (w.x * w.x + w.y * w.y) / z2;
  return 0.5f * (std::sqrt(1.0f + alpha2_tan2) - 1.0f);
}

Vec3 GgxDistribution::sample_visible_normal(const Vec3& wo, const Vec2& u) const {
  // Stretch to the configuration where the microsurface is a hemisphere of radius 1,
  // sample the visible part of its projected disk, and unstretch.
  const Vec3 v = glm::normalize(Vec3(alpha_ * wo.x, alpha_ * wo.y, wo.z));
  const float len2 = v.x * v.x + v.y * v.y;
  const Vec3 t1 = len2 > 0.0f ? Vec3(-v.y, v.x, 0.0f) / std::sqrt(len2) : Vec3(1, 0, 0);
  const Vec3 t2 = glm::cross(v, t1);
  // Uniform point on the unit disk, then warp the lower half onto the part of the
  // projected hemisphere that faces v (it shrinks to a half-ellipse at grazing v).
  const float r = std::sqrt(u.x);
  const float phi = kTwoPi * u.y;
  const float p1 = r * std::cos(phi);
  float p2 = r * std::sin(phi);
  const float s = 0.5f * (1.0f + v.z);
  p2 = (1.0f - s) * safe_sqrt(1.0f - p1 * p1) + s * p2;
  const Vec3 n_h = p1 * t1 + p2 * t2 + safe_sqrt(1.0f - p1 * p1 - p2 * p2) * v;
  return glm::normalize(Vec3(alpha_ * n_h.x, alpha_ * n_h.y, glm::max(n_h.z, 1e-7f)));
}

float GgxDistribution::visible_normal_pdf(const Vec3& wo, const Vec3& m) const {
  if (wo.z <= 0.0f) return 0.0f;
  const float wo_dot_m = glm::dot(wo, m);
  if (wo_dot_m <= 0.0f) return 0.0f;
  return G1(wo) * wo_dot_m * D(m) / wo.z;
}

float GgxDistribution::reflection_pdf(const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  const Vec3 h = reflection_half_vector(wo, wi);
  return G1(wo) * D(h) / (4.0f * wo.z);
}

float BeckmannDistribution::D(const Vec3& m) const {
  if (m.z <= 0.0f) return 0.0f;
  const float cos2 = m.z * m.z;
  const float tan2 = (m.x * m.x + m.y * m.y) / cos2;
  const float a2 = alpha_ * alpha_;
  // exp(-x) / cos^4 is zero well before either part underflows (which would give 0 / 0).
  if (!(tan2 / a2 < 80.0f)) return 0.0f;
  return std::exp(-tan2 / a2) / (kPi * a2 * cos2 * cos2);
}

float BeckmannDistribution::lambda(const Vec3& w) const {
  const float sin = std::sqrt(w.x * w.x + w.y * w.y);
  if (sin == 0.0f) return 0.0f;
  if (w.z == 0.0f) return kInfinity;
  const float a = std::abs(w.z) / (alpha_ * sin);  // 1 / (alpha tan theta)
  return 0.5f * (std::erf(a) - 1.0f) + std::exp(-a * a) / (2.0f * a * std::sqrt(kPi));
}

Vec3 BeckmannDistribution::sample_normal(const Vec2& u) const {
  // Inverting the cdf of tan^2 theta, which is exponential with mean alpha^2.
  const float tan2 = -alpha_ * alpha_ * std::log1p(-glm::min(u.x, kOneMinusEpsilon));
  const float cos_theta = 1.0f / std::sqrt(1.0f + tan2);
  const float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
  const float phi = kTwoPi * u.y;
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

namespace {
Vec3 upper(const Vec3& w) { return w.z < 0.0f ? -w : w; }
}  // namespace

Vec3 MicrofacetDistribution::sample_normal(const Vec3& wo, const Vec2& u) const {
  return type_ == MicrofacetType::Ggx ? ggx_.sample_visible_normal(upper(wo), u)
                                      : beckmann_.sample_normal(u);
}

float MicrofacetDistribution::normal_pdf(const Vec3& wo, const Vec3& m) const {
  if (type_ == MicrofacetType::Beckmann) return beckmann_.D(m) * glm::max(m.z, 0.0f);
  return ggx_.visible_normal_pdf(upper(wo), m);
}

float MicrofacetDistribution::reflection_pdf(const Vec3& wo, const Vec3& wi) const {
  if (wo.z * wi.z <= 0.0f) return 0.0f;
  const Vec3 h = reflection_half_vector(upper(wo), upper(wi));
  const float wo_dot_h = glm::dot(upper(wo), h);
  if (wo_dot_h <= 0.0f) return 0.0f;
  return normal_pdf(wo, h) / (4.0f * wo_dot_h);
}

}  // namespace emlt
