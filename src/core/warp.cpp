#include "emlt/core/warp.h"

namespace emlt {

Vec2 square_to_uniform_disk_concentric(const Vec2& u) {
  // Shirley-Chiu concentric map: keeps strata compact, which helps lens sampling.
  const float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
  if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
  float sin_t, cos_t;
  if (std::abs(a) > std::abs(b)) {
    // phi = (pi/4) (b/a), within [-pi/4, pi/4]
    sin_cos_within_quarter((kPi / 4.0f) * (b / a), &sin_t, &cos_t);
    return {a * cos_t, a * sin_t};
  }
  // phi = pi/2 - t with t = (pi/4) (a/b): cos phi = sin t, sin phi = cos t
  sin_cos_within_quarter((kPi / 4.0f) * (a / b), &sin_t, &cos_t);
  return {b * sin_t, b * cos_t};
}

Vec3 square_to_uniform_sphere(const Vec2& u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = safe_sqrt(1.0f - z * z);
  const Vec2 circle = unit_circle_point(u.y);
  return {r * circle.x, r * circle.y, z};
}

Vec3 square_to_uniform_hemisphere(const Vec2& u) {
  const float z = u.x;
  const float r = safe_sqrt(1.0f - z * z);
  const Vec2 circle = unit_circle_point(u.y);
  return {r * circle.x, r * circle.y, z};
}

Vec3 square_to_cosine_hemisphere(const Vec2& u) {
  // Malley's method: uniform disk lifted to the hemisphere.
  const Vec2 d = square_to_uniform_disk_concentric(u);
  const float z = safe_sqrt(1.0f - d.x * d.x - d.y * d.y);
  return {d.x, d.y, glm::max(z, 1e-7f)};
}

Vec3 square_to_uniform_cone(const Vec2& u, float cos_max) {
  const float z = 1.0f - u.x * (1.0f - cos_max);
  const float r = safe_sqrt(1.0f - z * z);
  const Vec2 circle = unit_circle_point(u.y);
  return {r * circle.x, r * circle.y, z};
}

Vec2 square_to_uniform_triangle(const Vec2& u) {
  // Heitz 2019 low-distortion map: no square root, no fold.
  float b0, b1;
  if (u.x < u.y) {
    b0 = u.x / 2.0f;
    b1 = u.y - b0;
  } else {
    b1 = u.y / 2.0f;
    b0 = u.x - b1;
  }
  return {b0, b1};
}

Vec3 latlong_to_direction(const Vec2& uv) {
  const float phi = uv.x * kTwoPi;
  const float theta = uv.y * kPi;
  const float sin_theta = std::sin(theta);
  return {sin_theta * std::sin(phi), std::cos(theta), -sin_theta * std::cos(phi)};
}

Vec2 direction_to_latlong(const Vec3& d) {
  float phi = std::atan2(d.x, -d.z);
  if (phi < 0.0f) phi += kTwoPi;
  const float theta = safe_acos(d.y);
  return {glm::min(phi * kInvTwoPi, kOneMinusEpsilon), theta * kInvPi};
}

}  // namespace emlt
