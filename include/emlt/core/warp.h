#pragma once
// Warps from the unit square to common domains, each paired with its density. Directions
// are in a local frame (z up); densities are per unit solid angle unless stated otherwise.
#include "emlt/core/math.h"

namespace emlt {

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
