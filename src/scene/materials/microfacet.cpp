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

}  // namespace emlt
