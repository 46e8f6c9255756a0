#include "emlt/core/warp.h"

namespace emlt {

Vec2 square_to_uniform_disk_concentric(const Vec2& u) {
  // Shirley-Chiu concentric map: keeps strata compact, which helps lens sampling.
  const float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
  if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
  float r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (kPi / 4.0f) * (b / a);
  } else {
    r = b;
    phi = kPi / 2.0f - (kPi / 4.0f) * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

Vec3 square_to_uniform_sphere(const Vec2& u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = safe_sqrt(1.0f - z * z);
  const float phi = kTwoPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 square_to_uniform_hemisphere(const Vec2& u) {
  const float z = u.x;
  const float r = safe_sqrt(1.0f - z * z);
  const float phi = kTwoPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
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
  const float phi = kTwoPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
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
