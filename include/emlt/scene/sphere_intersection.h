#pragma once
// Where a ray meets a sphere: both roots of |o + t d - c|^2 = r^2, computed so that they
// stay accurate for rays from far away (|o - c| >> r) and for grazing rays, where the
// textbook b^2 - 4ac loses most of its digits to cancellation, and with the root of the
// smaller magnitude taken from the product of the roots rather than from -b + sqrt(...).
#include <cmath>

#include "emlt/core/math.h"

namespace emlt {

struct SphereRoots {
  float near = 0.0f, far = 0.0f;  // near <= far
};

// False when the line misses the sphere (or the direction is zero). The roots may lie
// behind the origin or beyond any segment: range checks are the caller's.
inline bool sphere_roots(const Vec3& center, float radius, const Vec3& origin,
                         const Vec3& direction, SphereRoots* roots) {
  const Vec3 f = origin - center;
  const float a = glm::dot(direction, direction);
  const float half_b = glm::dot(f, direction);
  if (!(a > 0.0f)) return false;
  // b^2/4 - ac = a (r^2 - |l|^2), l the offset from the centre to the line's closest
  // point. l is computed directly, so a far origin's |o - c|^2 does not swamp the
  // difference as it does in b^2/4 - ac (which keeps only the digits of |o - c|^2).
  const Vec3 l = f - (half_b / a) * direction;
  const float discriminant = a * (radius * radius - glm::dot(l, l));
  if (!(discriminant >= 0.0f)) return false;
  const float c = glm::dot(f, f) - radius * radius;
  // The root whose terms add without cancelling comes from q; the other from the product
  // of the roots, c / a = t0 t1 (Vieta).
  const float q = -(half_b + std::copysign(std::sqrt(discriminant), half_b));
  if (q == 0.0f) {  // tangent at the origin itself: a single root at t = 0
    roots->near = roots->far = 0.0f;
    return true;
  }
  const float t0 = q / a, t1 = c / q;
  roots->near = std::min(t0, t1);
  roots->far = std::max(t0, t1);
  return true;
}

}  // namespace emlt
