#pragma once
// Warps from the unit square to common domains, each paired with its density. Directions
// are in a local frame (z up); densities are per unit solid angle unless stated otherwise.
#include "emlt/core/math.h"

namespace emlt {

// sin and cos of an angle within [-pi/4, pi/4]: Taylor polynomials to x^9 and x^10, whose
// truncation error there (below 2e-9) is under a float's rounding, so no range reduction
// and no libm call are needed. Sampling routines reduce their angles to this range.
inline void sin_cos_within_quarter(float x, float* sin_x, float* cos_x) {
  const float x2 = x * x;
  *sin_x =
      x * (1.0f + x2 * (-1.0f / 6.0f +
                        x2 * (1.0f / 120.0f + x2 * (-1.0f / 5040.0f + x2 * (1.0f / 362880.0f)))));
  *cos_x = 1.0f + x2 * (-0.5f + x2 * (1.0f / 24.0f +
                                      x2 * (-1.0f / 720.0f +
                                            x2 * (1.0f / 40320.0f + x2 * (-1.0f / 3628800.0f)))));
}

// (cos 2 pi u, sin 2 pi u) for u in [0, 1]: the nearest quarter turn is taken out exactly
// (4u and its distance to an integer are exact in float), the rest is within a quarter.
// More accurate than sincosf(2 pi u), whose argument is rounded before the call.
inline Vec2 unit_circle_point(float u) {
  const float turns = 4.0f * u;
  const int quarter = int(turns + 0.5f);  // nearest for turns >= 0, without a libm call
  float s, c;
  sin_cos_within_quarter((turns - float(quarter)) * (kPi / 2.0f), &s, &c);
  switch (quarter & 3) {
    case 0:
      return {c, s};
    case 1:
      return {-s, c};
    case 2:
      return {-c, -s};
    default:
      return {s, -c};
  }
}

Vec2 square_to_uniform_disk_concentric(const Vec2& u);  // density 1/pi per unit area
Vec3 square_to_uniform_sphere(const Vec2& u);
inline float uniform_sphere_pdf() { return kInvFourPi; }
Vec3 square_to_uniform_hemisphere(const Vec2& u);
inline float uniform_hemisphere_pdf(const Vec3& w) { return w.z > 0 ? kInvTwoPi : 0.0f; }
Vec3 square_to_cosine_hemisphere(const Vec2& u);
inline float cosine_hemisphere_pdf(const Vec3& w) { return w.z > 0 ? w.z * kInvPi : 0.0f; }
// Uniform over the spherical cap of directions within acos(cos_max) of +z.
Vec3 square_to_uniform_cone(const Vec2& u, float cos_max);
inline float uniform_cone_pdf(float cos_max) { return 1.0f / (kTwoPi * (1.0f - cos_max)); }
// Barycentric coordinates (b1, b2) uniform over a triangle; b0 = 1 - b1 - b2.
Vec2 square_to_uniform_triangle(const Vec2& u);

// Lat-long parametrisation used by environment maps: u in [0,1) is azimuth phi/(2 pi),
// v in [0,1] is theta/pi with theta measured from +y (the "up" axis of the map).
Vec3 latlong_to_direction(const Vec2& uv);
Vec2 direction_to_latlong(const Vec3& d);

}  // namespace emlt
