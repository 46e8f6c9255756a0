#pragma once
#include "emlt/core/math.h"

namespace emlt {

struct Ray {
  Vec3 origin{0.0f};
  Vec3 direction{0.0f, 0.0f, 1.0f};  // unit length
  float tmin = 0.0f;
  float tmax = kInfinity;
};

// Moves a surface point off the surface along the geometric normal, on the side `dir`
// leaves towards, by an amount that scales with the point's magnitude (float spacing).
inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& ng, const Vec3& dir) {
  const float scale = 1e-4f * glm::max(1.0f, glm::max(std::abs(p.x), glm::max(std::abs(p.y), std::abs(p.z))));
  return p + (glm::dot(ng, dir) >= 0.0f ? scale : -scale) * ng;
}

inline Ray spawn_ray(const Vec3& p, const Vec3& ng, const Vec3& dir) {
  return Ray{offset_ray_origin(p, ng, dir), dir, 0.0f, kInfinity};
}

}  // namespace emlt
