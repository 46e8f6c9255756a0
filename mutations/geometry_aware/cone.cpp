#include "mutations/geometry_aware/cone.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace emlt::geometry_aware {

double estimate_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                                double alpha_min, double alpha_max) {
  if (apex.is_environment() || other.is_environment()) return alpha_max;
  const Vec3 a = apex.position, b = other.position;
  const Vec3 axis = b - a;
  const float length = glm::length(axis);
  if (!(length > 0.0f)) return alpha_min;
  // Surfaces within this distance of an endpoint are the endpoint's own (ray-hit positions
  // carry float error of about 1e-7 |p|; spawn offsets are 1e-4 |p|).
  const float scale = std::max({1.0f, std::abs(a.x), std::abs(a.y), std::abs(a.z), std::abs(b.x),
                                std::abs(b.y), std::abs(b.z)});
  const float ignore_eps = 2e-4f * scale;
  const Vec3 ends[2] = {a, b};
  double best = std::min(alpha_max, 0.5 * M_PI);
  for (const double t : kConeProbes) {
    const double s = t * double(length);
    const Vec3 p = a + float(t) * axis;
    // Only surfaces nearer than s·tan(best) can lower the estimate (best < π/2 here).
    const float radius = float(s * std::tan(std::min(best, 0.5 * M_PI - 1e-6)));
    if (!(radius > 0.0f)) break;
    const float r = scene.clearance(p, radius, ends, 2, ignore_eps);
    if (r < radius) best = std::atan(double(r) / s);
  }
  return std::clamp(best, alpha_min, alpha_max);
}

namespace {

struct CacheEntry {
  const Scene* scene = nullptr;
  Vec3 apex{0.0f}, other{0.0f};
  double alpha_min = 0.0, alpha_max = 0.0, alpha = 0.0;
};

// Recent results of this thread: a chain's step needs the cones of x (proposed, and cached,
// one step earlier) and of y. Exact key comparison, so a hit returns the same bits as a
// recomputation: determinism does not depend on the cache or on thread scheduling.
struct ConeCache {
  std::array<CacheEntry, 32> entries;
  size_t next = 0;
};

bool same(const PathVertex& v, const Vec3& p) {
  return v.position.x == p.x && v.position.y == p.y && v.position.z == p.z;
}

}  // namespace

double cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                       double alpha_min, double alpha_max) {
  if (apex.is_environment() || other.is_environment()) return alpha_max;
  thread_local ConeCache cache;
  for (const CacheEntry& e : cache.entries)
    if (e.scene == &scene && e.alpha_min == alpha_min && e.alpha_max == alpha_max && same(apex, e.apex) &&
        same(other, e.other))
      return e.alpha;
  const double alpha = estimate_cone_half_angle(scene, apex, other, alpha_min, alpha_max);
  cache.entries[cache.next] = {&scene, apex.position, other.position, alpha_min, alpha_max, alpha};
  cache.next = (cache.next + 1) % cache.entries.size();
  return alpha;
}

}  // namespace emlt::geometry_aware
