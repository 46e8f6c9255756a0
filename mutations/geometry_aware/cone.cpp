#include "mutations/geometry_aware/cone.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

namespace emlt::geometry_aware {

namespace {

// Coordinates relative to the apex; u the unit axis; s = q·u the axial distance.
struct Axis {
  DVec3 u;
  double s_lo, s_hi;  // the span the cone is checked over
};

// tan of the angle between q (s = q·u > 0) and the axis.
double tan_from_axis(const DVec3& q, const Axis& axis) {
  const double s = glm::dot(q, axis.u);
  return glm::length(q - s * axis.u) / s;
}

// The smallest tan over the open segment p0 p1 (both with s > 0). With q(t) = p0 + t d,
// cos θ(t) = (A + tB) / √(C + 2tD + t²E), A = p0·u, B = d·u, C = |p0|², D = p0·d, E = |d|².
// Setting the derivative of cos² to zero (A + tB > 0 divides out) leaves a linear equation,
//     (BC − AD) + t (BD − AE) = 0,
// so the extremes are the ends and at most one interior point.
// The ends' values are the caller's (each polygon vertex is evaluated once).
double segment_interior_min_tan(const DVec3& p0, const DVec3& p1, const Axis& axis) {
  double best = std::numeric_limits<double>::infinity();
  const DVec3 d = p1 - p0;
  const double a = glm::dot(p0, axis.u), b = glm::dot(d, axis.u), c = glm::dot(p0, p0), e = glm::dot(d, d),
               dd = glm::dot(p0, d);
  const double denominator = b * dd - a * e;
  if (denominator != 0.0) {
    const double t = (a * dd - b * c) / denominator;
    if (t > 0.0 && t < 1.0) best = std::min(best, tan_from_axis(p0 + t * d, axis));
  }
  return best;
}

// Clips a convex polygon to s ≥ bound (sign = +1) or s ≤ bound (sign = −1) (Sutherland–Hodgman).
int clip(const DVec3* in, int n, DVec3* out, const Axis& axis, double bound, double sign) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const DVec3 &p = in[i], &q = in[(i + 1) % n];
    const double dp = sign * (glm::dot(p, axis.u) - bound), dq = sign * (glm::dot(q, axis.u) - bound);
    if (dp >= 0.0) out[m++] = p;
    if ((dp >= 0.0) != (dq >= 0.0)) out[m++] = p + (dp / (dp - dq)) * (q - p);
  }
  return m;
}

// The smallest tan of the angle from the axis over the triangle's part in the span, or
// +∞ when none of it is in the span. On a plane, θ has convex sublevel sets for θ < π/2
// (a convex cone cut by a plane), so its only local minimum is where the axis meets the
// plane (θ = 0): the minimum over a convex polygon is 0 if the polygon holds that point,
// otherwise it lies on the boundary.
double triangle_min_tan(const DVec3& q0, const DVec3& q1, const DVec3& q2, const Axis& axis) {
  const DVec3 n = glm::cross(q1 - q0, q2 - q0);
  const double nu = glm::dot(n, axis.u);
  if (nu != 0.0) {
    const double s = glm::dot(n, q0) / nu;
    if (s >= axis.s_lo && s <= axis.s_hi) {
      const DVec3 h = s * axis.u;
      const double e0 = glm::dot(n, glm::cross(q1 - q0, h - q0)), e1 = glm::dot(n, glm::cross(q2 - q1, h - q1)),
                   e2 = glm::dot(n, glm::cross(q0 - q2, h - q2));
      if (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) return 0.0;
    }
  }
  DVec3 a[5] = {q0, q1, q2}, b[5];
  int count = clip(a, 3, b, axis, axis.s_lo, 1.0);
  count = clip(b, count, a, axis, axis.s_hi, -1.0);
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < count; ++i)
    best = std::min({best, tan_from_axis(a[i], axis), segment_interior_min_tan(a[i], a[(i + 1) % count], axis)});
  return best;
}

// The search's state: the current tan α, lowered by each surface found to be nearer the axis.
struct ConeSearch {
  DVec3 apex;
  Axis axis;
  const Vec3* ends = nullptr;
  float ignore_eps = 0.0f;
  double tan_alpha = 0.0, sin_alpha = 0.0, cos_alpha = 1.0, guard = 0.0, length = 0.0;
  // The box of the cone over the span, relative to the apex: the cone is the hull of the
  // apex and its disc at s_hi (centre s_hi u, radius ρ = s_hi tan α), whose extent along
  // axis i is ρ √(1 − u_i²). Widened by the guard.
  DVec3 box_lower{0.0}, box_upper{0.0};

  void lower(double t) {
    tan_alpha = t;
    cos_alpha = 1.0 / std::sqrt(1.0 + t * t);
    sin_alpha = t * cos_alpha;
    const DVec3 centre = axis.s_hi * axis.u;
    const DVec3 reach = axis.s_hi * t * glm::sqrt(glm::max(DVec3(0.0), DVec3(1.0) - axis.u * axis.u));
    box_lower = glm::min(DVec3(0.0), centre - reach) - guard;
    box_upper = glm::max(DVec3(0.0), centre + reach) + guard;
  }

  // How far a box is outside the current cone within the span (≤ 0: it may hold a point
  // of the cone there; +∞ when it lies wholly before or beyond the span), by its bounding
  // sphere (centre c relative to the apex, radius r): with s = c·u and d = |c − s u|, c's
  // distance to the cone is d cos α − s sin α when the nearest point is on the cone's
  // surface, |c| (not less) when it is the apex, and ≤ 0 inside; the sphere meets the cone
  // when that is at most r. The guard and the relative slack keep float rounding of the
  // boxes on the safe side.
  double outside(const SurfaceBvh::Node& node) const {
    const DVec3 lower = DVec3(node.lower) - apex, upper = DVec3(node.upper) - apex;
    // Disjoint from the cone's box (cheap, and tight where the sphere is loose: a wall's
    // node beside a segment that runs along it).
    if (glm::any(glm::greaterThan(lower, box_upper)) || glm::any(glm::lessThan(upper, box_lower)))
      return std::numeric_limits<double>::infinity();
    return sphere_outside(0.5 * (lower + upper), 0.5 * glm::length(upper - lower) * (1.0 + 1e-6) + guard);
  }
  double sphere_outside(const DVec3& c, double r) const {
    const double s = glm::dot(c, axis.u);
    if (s + r < axis.s_lo || s - r > axis.s_hi) return std::numeric_limits<double>::infinity();
    const double d = glm::length(c - s * axis.u);
    return d * cos_alpha - s * sin_alpha - r;
  }

  void triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const DVec3 q0 = DVec3(a) - apex, q1 = DVec3(b) - apex, q2 = DVec3(c) - apex;
    // Cheap rejections, cheapest first. Wholly before or beyond the span:
    const double s0 = glm::dot(q0, axis.u), s1 = glm::dot(q1, axis.u), s2 = glm::dot(q2, axis.u);
    if (std::max({s0, s1, s2}) < axis.s_lo || std::min({s0, s1, s2}) > axis.s_hi) return;
    // Disjoint from the cone's box:
    if (glm::any(glm::greaterThan(glm::min(q0, glm::min(q1, q2)), box_upper)) ||
        glm::any(glm::lessThan(glm::max(q0, glm::max(q1, q2)), box_lower)))
      return;
    DVec3 nd = glm::cross(q1 - q0, q2 - q0);
    const double n_length = glm::length(nd);
    if (!(n_length > 0.0)) return;
    nd /= n_length;
    // n̂ oriented away from the apex: the plane is n̂·q = d, d ≥ 0 the apex's distance.
    double plane_distance = glm::dot(nd, q0);
    if (plane_distance < 0.0) nd = -nd, plane_distance = -plane_distance;
    const double nu = glm::dot(nd, axis.u);
    // An endpoint's own surface: the triangle's plane holds it (the far end, at L u, lies
    // L n̂·u − d from the plane).
    if (plane_distance < ignore_eps || std::abs(length * nu - plane_distance) < ignore_eps) return;
    // The whole plane outside the cone: the plane's points are seen in directions w with
    // n̂·w > 0; if n̂·u ≤ 0 the smallest angle from u among them is the angle to the plane
    // n̂·w = 0, asin(−n̂·u). The plane is out of reach when that is at least α: −n̂·u ≥ sin α.
    if (-nu >= sin_alpha) return;
    // The plane beyond the cone's reach over the span: the cone's points at axial distance
    // s reach at most s (n̂·u + tan α √(1 − (n̂·u)²)) along n̂. A side wall that the whole
    // segment runs along is rejected here instead of by the clipping below.
    if (axis.s_hi * (nu + tan_alpha * std::sqrt(std::max(0.0, 1.0 - nu * nu))) < plane_distance) return;
    // The triangle's bounding sphere (about its centroid) outside the cone: most triangles
    // that come this far lie beside the cone near an endpoint, and the exact angle below
    // costs several times this test.
    const DVec3 centroid = (q0 + q1 + q2) / 3.0;
    const double r = std::sqrt(std::max({glm::dot(q0 - centroid, q0 - centroid), glm::dot(q1 - centroid, q1 - centroid),
                                         glm::dot(q2 - centroid, q2 - centroid)})) * (1.0 + 1e-6) + guard;
    if (sphere_outside(centroid, r) > 0.0) return;
    const double t = triangle_min_tan(q0, q1, q2, axis);
    if (t < tan_alpha) lower(t);
  }

  void sphere(const Vec3& center, float sphere_radius) {
    for (int i = 0; i < 2; ++i)
      if (std::abs(glm::length(ends[i] - center) - sphere_radius) < ignore_eps) return;
    const DVec3 q = DVec3(center) - apex;
    const double rho = double(sphere_radius), s = glm::dot(q, axis.u), distance = glm::length(q);
    if (s - rho > axis.s_hi || s + rho < 0.0) return;  // wholly outside the span
    // The whole sphere's smallest angle (a lower bound on its part in the span's).
    double t = 0.0;
    if (distance > rho) {
      const double theta = std::atan2(glm::length(q - s * axis.u), s) - std::asin(rho / distance);
      if (theta >= 0.5 * M_PI) return;
      t = theta > 0.0 ? std::tan(theta) : 0.0;
    }
    if (t < tan_alpha) lower(t);
  }
};

}  // namespace

double estimate_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                                double alpha_min, double alpha_max) {
  if (apex.is_environment() || other.is_environment()) return alpha_max;
  const DVec3 a(apex.position), b(other.position);
  const double length = glm::length(b - a);
  if (!(length > 0.0)) return alpha_min;
  // Surfaces within this distance of an endpoint are the endpoint's own (ray-hit positions
  // carry float error of about 1e-7 |p|; spawn offsets are 1e-4 |p|).
  const float scale = std::max({1.0f, std::abs(apex.position.x), std::abs(apex.position.y), std::abs(apex.position.z),
                                std::abs(other.position.x), std::abs(other.position.y), std::abs(other.position.z)});
  const Vec3 ends[2] = {apex.position, other.position};
  ConeSearch search;
  search.apex = a;
  search.axis = {(b - a) / length, 1e-9 * length, length * (1.0 - kConeEndMargin)};
  search.ends = ends;
  search.ignore_eps = 2e-4f * scale;
  // Float rounding of the boxes, relative to the apex.
  search.guard = 1e-6 * double(scale);
  // Below π/2 (a half-space) so that tan α stays finite.
  search.lower(std::tan(std::min(alpha_max, 0.5 * M_PI - 1e-6)));
  search.length = length;
  const double tan_alpha_min = std::tan(alpha_min);
  const SurfaceBvh& bvh = scene.surface_bvh();
  for (const SurfaceBvh::Sphere& sphere : bvh.spheres()) search.sphere(sphere.center, sphere.radius);
  if (!(search.tan_alpha > tan_alpha_min)) return alpha_min;
  const auto& nodes = bvh.nodes();
  if (!nodes.empty() && search.outside(nodes[0]) <= 0.0) {
    // Depth first, each child tested when its parent is opened and the deeper one inside
    // the cone taken first: the limiting surface tends to be found early, and the cone
    // narrows before most nodes are reached. A node is tested again when it is taken only
    // if α shrank after it was pushed. The order does not change the result (the smallest
    // angle over every surface in the final cone). The depth is at most log(n/4)/log(8/7)
    // (surface_bvh.cpp's split keeps an eighth on each side), under 160 for any n < 2^32.
    struct Pending {
      uint32_t node;
      double tan_alpha;  // α's tan when the node was found to meet the cone
    };
    Pending stack[256];
    int top = 0;
    stack[top++] = {0, search.tan_alpha};
    while (top > 0) {
      const Pending pending = stack[--top];
      const SurfaceBvh::Node& node = nodes[pending.node];
      if (search.tan_alpha < pending.tan_alpha && search.outside(node) > 0.0) continue;
      if (node.count > 0) {
        for (uint32_t i = node.first; i < node.first + node.count; ++i) {
          const SurfaceBvh::Corners corner = bvh.corners(i);
          search.triangle(corner.a, corner.b, corner.c);
        }
        if (!(search.tan_alpha > tan_alpha_min)) return alpha_min;
        continue;
      }
      const uint32_t first = pending.node + 1, second = node.first;
      const double first_outside = search.outside(nodes[first]), second_outside = search.outside(nodes[second]);
      const bool first_deeper = first_outside <= second_outside;
      if (first_deeper ? second_outside <= 0.0 : first_outside <= 0.0)
        stack[top++] = {first_deeper ? second : first, search.tan_alpha};
      if (first_deeper ? first_outside <= 0.0 : second_outside <= 0.0)
        stack[top++] = {first_deeper ? first : second, search.tan_alpha};
    }
  }
  return std::clamp(std::atan(search.tan_alpha), alpha_min, alpha_max);
}

namespace {

struct CacheEntry {
  const Scene* scene = nullptr;
  Vec3 apex{0.0f}, other{0.0f};
  double alpha_min = 0.0, alpha_max = 0.0, alpha = 0.0;
};

// Recent results of this thread: a chain's step needs the cones of x (proposed, and cached,
// one step earlier) and of y. Exact key comparison, so a hit returns the same bits as a
// recomputation: determinism does not depend on the cache, its replacement policy or thread
// scheduling. Direct-mapped by a hash of the key: a linear scan of the entries cost as much
// as a tenth of an estimate on every call.
struct ConeCache {
  static constexpr size_t kSize = 128;
  std::array<CacheEntry, kSize> entries;
};

uint64_t bits(float f) {
  uint32_t u = 0;
  std::memcpy(&u, &f, sizeof(u));
  return u;
}

uint64_t bits(double d) {
  uint64_t u = 0;
  std::memcpy(&u, &d, sizeof(u));
  return u;
}

size_t slot_of(const Vec3& apex, const Vec3& other, double alpha_min, double alpha_max) {
  uint64_t h = 0x9E3779B97F4A7C15ull;
  for (const uint64_t b : {bits(apex.x), bits(apex.y), bits(apex.z), bits(other.x), bits(other.y), bits(other.z),
                           bits(alpha_min), bits(alpha_max)})
    h = (h ^ b) * 0xff51afd7ed558ccdull;
  return size_t(h >> 57) % ConeCache::kSize;
}

bool same(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

}  // namespace

double cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other, double alpha_min,
                       double alpha_max) {
  if (apex.is_environment() || other.is_environment()) return alpha_max;
  thread_local ConeCache cache;
  CacheEntry& e = cache.entries[slot_of(apex.position, other.position, alpha_min, alpha_max)];
  if (e.scene == &scene && e.alpha_min == alpha_min && e.alpha_max == alpha_max &&
      same(e.apex, apex.position) && same(e.other, other.position))
    return e.alpha;
  const double alpha = estimate_cone_half_angle(scene, apex, other, alpha_min, alpha_max);
  e = {&scene, apex.position, other.position, alpha_min, alpha_max, alpha};
  return alpha;
}

}  // namespace emlt::geometry_aware
