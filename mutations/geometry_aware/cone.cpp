#include "mutations/geometry_aware/cone.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "mutations/geometry_aware/cone_cells.h"

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace emlt::geometry_aware {

namespace {

constexpr uint32_t kNoTriangle = ~uint32_t(0);

// A node's four children at once (GCC's vector extensions: one SSE register on x86-64's
// baseline).
using Float4 = float __attribute__((vector_size(16)));
using Mask4 = int32_t __attribute__((vector_size(16)));

[[gnu::always_inline]] inline Float4 load4(const float* p) {
  Float4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

[[gnu::always_inline]] inline Float4 abs4(Float4 x) {
  return Float4(Mask4(x) & 0x7fffffff);
}

[[gnu::always_inline]] inline Float4 sqrt4(Float4 x) {
#if defined(__SSE__)
  return Float4(_mm_sqrt_ps(__m128(x)));
#else
  for (int i = 0; i < 4; ++i) x[i] = std::sqrt(x[i]);
  return x;
#endif
}

// One bit per lane whose mask is set (lane 0 in bit 0).
[[gnu::always_inline]] inline unsigned lane_bits(Mask4 m) {
#if defined(__SSE__)
  return unsigned(_mm_movemask_ps(__m128(m)));
#else
  unsigned bits = 0;
  for (int lane = 0; lane < 4; ++lane) bits |= unsigned(m[lane] != 0) << lane;
  return bits;
#endif
}

// The nearest floats at or below and at or above x (finite x; one step of the bits instead
// of nextafter, a library call, since the cone's box is rounded at every lowering of α).
float float_below(double x) {
  const float f = float(x);
  if (double(f) <= x) return f;
  return f > 0.0f   ? std::bit_cast<float>(std::bit_cast<uint32_t>(f) - 1)
         : f < 0.0f ? std::bit_cast<float>(std::bit_cast<uint32_t>(f) + 1)
                    : -std::numeric_limits<float>::denorm_min();
}
float float_above(double x) {
  return -float_below(-x);
}

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
    // The hull of the discs at s_lo and s_hi (s_lo near 0 for the whole segment: the apex).
    const DVec3 across = t * glm::sqrt(glm::max(DVec3(0.0), DVec3(1.0) - axis.u * axis.u));
    const DVec3 near_centre = axis.s_lo * axis.u, far_centre = axis.s_hi * axis.u;
    box_lower = glm::min(near_centre - axis.s_lo * across, far_centre - axis.s_hi * across) - guard;
    box_upper = glm::max(near_centre + axis.s_lo * across, far_centre + axis.s_hi * across) + guard;
    cos_f = float(cos_alpha), sin_f = float(sin_alpha);
    for (int i = 0; i < 3; ++i) {
      box_lower_f[i] = float_below(apex[i] + box_lower[i]);
      box_upper_f[i] = float_above(apex[i] + box_upper[i]);
    }
  }

  // The same in float for the node tests (meets): the apex, the axis, cos α and sin α
  // rounded, and the cone's box in scene coordinates rounded outwards.
  float apex_f[3] = {}, u_f[3] = {}, cos_f = 1.0f, sin_f = 0.0f, s_lo_f = 0.0f, s_hi_f = 0.0f,
        guard_f = 0.0f;
  float box_lower_f[3] = {}, box_upper_f[3] = {};

  // Which of a node's children may meet the current cone within the span, as lane bits,
  // and for each lane its sphere's axial distance s, distance d from the axis and radius
  // (with the margin), from which a later test at a smaller α is d cos α − s sin α −
  // radius > 0, and how far it is outside the cone now (≤ 0 for the lanes returned). The
  // test is the cone's box against the child's, then the tangent plane of the cone that
  // faces the box's centre c (through the apex, normal m = ŵ cos α − u sin α, ŵ the unit
  // direction from the axis to c): the cone lies in m·q ≤ 0, and the box lies beyond it
  // when m·c exceeds the box's half-extents weighted by |m|'s components, which is never
  // looser than the bounding sphere (|m| = 1) and much tighter for the flat boxes of walls
  // and floors. Float rounding (about 50 ulps of |c| + r over the whole computation, u, α
  // and the apex's offset included) is covered by a margin of 1e-5 (|s| + d + r), so a
  // child is dropped only where it truly misses the cone: the walk opens a few more nodes
  // than an exact test would, and finds the same minimum. (In double, one child at a time,
  // the sphere test cost about 57 instructions; the four lanes here cost about 175.) The
  // depth order takes the lanes by outside / (|s| + d + radius), about the angle by which
  // each misses the axis: a child seen under a wide angle (near the apex) is taken before a
  // far one of the same distance, and on the terrain the limiting surface is found sooner
  // (chains 0.13 -> 0.19 M/s) with no loss elsewhere.
  unsigned meets(const SurfaceBvh::Node& node, Float4* s_out, Float4* d_out, Float4* radius_out,
                 Float4* outside_out) const {
    Mask4 in_box = Mask4{} - 1;
    Float4 c[3], h[3];
    for (int i = 0; i < 3; ++i) {
      const Float4 lower = load4(node.lower[i]), upper = load4(node.upper[i]);
      in_box &= (lower <= box_upper_f[i]) & (upper >= box_lower_f[i]);
      c[i] = 0.5f * (lower + upper) - apex_f[i];
      h[i] = 0.5f * (upper - lower);
    }
    const Float4 s = c[0] * u_f[0] + c[1] * u_f[1] + c[2] * u_f[2];
    const Float4 p[3] = {c[0] - s * u_f[0], c[1] - s * u_f[1], c[2] - s * u_f[2]};
    const Float4 d = sqrt4(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    const Float4 r = sqrt4(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    const Float4 margin = 1e-5f * (abs4(s) + d + r) + guard_f;
    const Float4 radius = r + margin;
    const Mask4 in_span = (s + radius >= s_lo_f) & (s - radius <= s_hi_f);
    // m = ŵ cos α − u sin α; a centre on the axis (d = 0) leaves m = −u sin α, the plane
    // through the apex across the axis, which the cone lies behind as well.
    const Float4 scale = cos_f / (d + 1e-30f);
    Float4 reach = margin;
    for (int i = 0; i < 3; ++i) reach += abs4(p[i] * scale - u_f[i] * sin_f) * h[i];
    const Float4 outside = d * cos_f - s * sin_f - reach;
    *s_out = s, *d_out = d, *radius_out = radius, *outside_out = outside / (abs4(s) + d + radius);
    return lane_bits(in_box & in_span & (outside <= 0.0f));
  }

  // The triangle that last lowered α (the limiting one so far), or kNoTriangle.
  uint32_t limiting = kNoTriangle;

  void triangle(uint32_t index, const Vec3& a, const Vec3& b, const Vec3& c) {
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
    // The triangle beyond the tangent plane of the cone that faces its centroid (as for the
    // nodes: the cone lies in m·q ≤ 0): most triangles that come this far lie beside the
    // cone near an endpoint, and the exact angle below costs several times this test. The
    // tolerance, 1e-9 of each corner's size, is far above the rounding of m·q.
    const DVec3 centroid = (q0 + q1 + q2) / 3.0;
    const DVec3 across = centroid - glm::dot(centroid, axis.u) * axis.u;
    const double across_length = glm::length(across);
    if (across_length > 0.0) {
      const DVec3 m = across * (cos_alpha / across_length) - axis.u * sin_alpha;
      const auto beyond = [&m](const DVec3& q) {
        return glm::dot(m, q) > 1e-9 * (std::abs(q.x) + std::abs(q.y) + std::abs(q.z));
      };
      if (beyond(q0) && beyond(q1) && beyond(q2)) return;
    }
    const double t = triangle_min_tan(q0, q1, q2, axis);
    if (t < tan_alpha) lower(t), limiting = index;
  }

  void sphere(const Vec3& center, float sphere_radius) {
    for (int i = 0; i < 2; ++i)
      if (std::abs(glm::length(ends[i] - center) - sphere_radius) < ignore_eps) return;
    const DVec3 q = DVec3(center) - apex;
    const double rho = double(sphere_radius), s = glm::dot(q, axis.u), distance = glm::length(q);
    if (s - rho > axis.s_hi || s + rho < axis.s_lo) return;  // wholly outside the span
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

// The walk over the axial span [s_lo, s_hi] of the segment apex -> other (length L > 0),
// from tan α = tan_start down: the smallest tan over the surfaces in that part of the cone,
// or at most tan_min once it is reached (the caller's floor).
double walk_span(const Scene& scene, const PathVertex& apex, const PathVertex& other, double length,
                 double s_lo, double s_hi, double tan_start, double tan_min,
                 uint32_t* hint = nullptr) {
  const DVec3 a(apex.position), b(other.position);
  // Surfaces within this distance of an endpoint are the endpoint's own (ray-hit positions
  // carry float error of about 1e-7 |p|; spawn offsets are 1e-4 |p|).
  const float scale = std::max({1.0f, std::abs(apex.position.x), std::abs(apex.position.y), std::abs(apex.position.z),
                                std::abs(other.position.x), std::abs(other.position.y), std::abs(other.position.z)});
  const Vec3 ends[2] = {apex.position, other.position};
  ConeSearch search;
  search.apex = a;
  search.axis = {(b - a) / length, s_lo, s_hi};
  search.ends = ends;
  search.ignore_eps = 2e-4f * scale;
  // Float rounding of the boxes, relative to the apex.
  search.guard = 1e-6 * double(scale);
  for (int i = 0; i < 3; ++i)
    search.apex_f[i] = apex.position[i], search.u_f[i] = float(search.axis.u[i]);
  search.s_lo_f = float_below(search.axis.s_lo), search.s_hi_f = float_above(search.axis.s_hi);
  search.guard_f = float(search.guard);
  search.lower(tan_start);
  search.length = length;
  const SurfaceBvh& bvh = scene.surface_bvh();
  for (const SurfaceBvh::Sphere& sphere : bvh.spheres()) search.sphere(sphere.center, sphere.radius);
  if (!(search.tan_alpha > tan_min)) return search.tan_alpha;
  const auto& nodes = bvh.nodes();
  if (nodes.empty()) return search.tan_alpha;
  // A candidate first (hint: the triangle that limited a recent cone from the same apex): if
  // it meets the cone it narrows it before the walk, which then opens fewer nodes, or ends
  // it at once at the floor. The result does not depend on it: the walk finds the smallest
  // angle over every surface in the final cone whatever the cone it starts from (it is
  // tested again where the walk reaches it, with the same value).
  // The walk then skips it: its angle is already in.
  uint32_t tested = kNoTriangle;
  if (hint && *hint < bvh.triangle_count()) {
    tested = *hint;
    const SurfaceBvh::Corners corner = bvh.corners(tested);
    search.triangle(tested, corner.a, corner.b, corner.c);
    if (!(search.tan_alpha > tan_min)) return search.tan_alpha;
  }
  const auto remember = [&] {
    if (hint && search.limiting != kNoTriangle) *hint = search.limiting;
  };
  // Depth first, the children that meet the cone taken deepest inside first (by angle, see
  // meets): the limiting surface tends to be found early, and the cone narrows before most
  // nodes are reached. A child waiting on the stack is tested again by its sphere when it is
  // taken, since α may have shrunk meanwhile. (A best-first walk, a heap by the same key,
  // reached the terrain's floor sooner still, 0.24 M/s, but cost the doors 10-15 %.) The order does
  // not change the result (the smallest angle over every surface in the final cone). The depth is
  // at most log(n/4)/log(8/7) (surface_bvh.cpp's split keeps an eighth on each side), under 160 for
  // any n < 2^32, and each level leaves at most three children waiting.
  struct Pending {
    uint32_t index, count;  // as in SurfaceBvh::Node's lanes
    float s, d, radius;     // its sphere, as meets() gives them
  };
  Pending stack[512];
  int top = 0;
  const auto open = [&](const SurfaceBvh::Node& node) {
    Float4 s, d, radius, outside;
    unsigned bits = search.meets(node, &s, &d, &radius, &outside);
    // Pushed most outside first, so that the deepest inside is taken next.
    int order[4], count = 0;
    for (; bits != 0; bits &= bits - 1) {
      const int lane = std::countr_zero(bits);
      int j = count++;
      for (; j > 0 && outside[order[j - 1]] < outside[lane]; --j) order[j] = order[j - 1];
      order[j] = lane;
    }
    for (int j = 0; j < count; ++j) {
      const int lane = order[j];
      stack[top++] = {node.index[lane], node.count[lane], s[lane], d[lane], radius[lane]};
    }
  };
  open(nodes[0]);
  while (top > 0) {
    const Pending pending = stack[--top];
    if (pending.d * search.cos_f - pending.s * search.sin_f - pending.radius > 0.0f) continue;
    if (pending.count == 0) {
      open(nodes[pending.index]);
      continue;
    }
    for (uint32_t i = pending.index; i < pending.index + pending.count; ++i) {
      if (i == tested) continue;
      const SurfaceBvh::Corners corner = bvh.corners(i);
      search.triangle(i, corner.a, corner.b, corner.c);
    }
    if (!(search.tan_alpha > tan_min)) {
      remember();
      return search.tan_alpha;
    }
  }
  remember();
  return search.tan_alpha;
}

// tan α_max, below π/2 (a half-space) so that it stays finite.
double tan_of_limit(double alpha_max) {
  return std::tan(std::min(alpha_max, 0.5 * M_PI - 1e-6));
}

// The cheap bound's march over [s_a, s_b] (cone.h): lowers *tan_alpha until the clearance
// balls of the samples cover the cone's discs; false once it is at or below tan_min.
bool march_field(const ClearanceField& field, const DVec3& a, const DVec3& u, double s_a,
                 double s_b, double slack, double tan_min, double* tan_alpha) {
  double t = *tan_alpha;
  int lowerings = 0, samples = 0;
  for (double s = s_a;; ++samples) {
    // A segment that runs through a narrow gap would take tiny steps: the floor instead.
    if (samples == kFieldMaxSamples) {
      *tan_alpha = tan_min;
      return false;
    }
    const double c = field.lower_bound(a + s * u) - slack;
    // The ball of radius c − |σ − s| about the axis point at σ ≥ s holds the cone's disc
    // of radius σ t while σ ≤ (c + s) / (1 + t).
    double step = (c - s * t) / (1.0 + t);
    const double least = kFieldLeastStep * c;
    if (step < least) {
      // The α at which this sample covers `least`; after too many lowerings, the floor.
      t = (c - least) / (s + least);
      if (!(t > tan_min) || ++lowerings > kFieldMaxLowerings) {
        *tan_alpha = std::min(t, tan_min);
        return false;
      }
      step = least;
    }
    if (s + step >= s_b) break;
    s += step;
  }
  *tan_alpha = t;
  return true;
}

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

// A hash of a cone's key in [0, 128).
size_t slot_of(const Vec3& apex, const Vec3& other, double alpha_min, double alpha_max) {
  uint64_t h = 0x9E3779B97F4A7C15ull;
  for (const uint64_t b : {bits(apex.x), bits(apex.y), bits(apex.z), bits(other.x), bits(other.y),
                           bits(other.z), bits(alpha_min), bits(alpha_max)})
    h = (h ^ b) * 0xff51afd7ed558ccdull;
  return size_t(h >> 57);
}

bool same(const Vec3& a, const Vec3& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

}  // namespace

ConeTan estimate_cone_tan(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                          double alpha_min, double alpha_max) {
  const double length = glm::length(DVec3(other.position) - DVec3(apex.position));
  const double tan_alpha_min = std::tan(alpha_min), tan_alpha_max = tan_of_limit(alpha_max);
  if (!(length > 0.0)) return {tan_alpha_min, tan_alpha_min, tan_alpha_max};
  // The triangle that limited this thread's last cone from the same apex, as the walk's first
  // candidate: a perturbation keeps one end of the segment it moves (the lens and caustic
  // moves' fixed vertex, the lens point), so y's cone is often limited by the surface that
  // limited x's. Only a hint: the walk's result does not depend on it (walk_span), so
  // neither the thread nor what ran on it before matter.
  struct Hint {
    const Scene* scene = nullptr;
    Vec3 apex{0.0f};
    uint32_t triangle = kNoTriangle;
  };
  thread_local std::array<Hint, 64> hints;
  Hint& hint = hints[slot_of(apex.position, apex.position, 0.0, 0.0) % hints.size()];
  if (hint.scene != &scene || !same(hint.apex, apex.position))
    hint = {&scene, apex.position, kNoTriangle};
  const double t =
      walk_span(scene, apex, other, length, 1e-9 * length, length * (1.0 - kConeEndMargin),
                tan_alpha_max, tan_alpha_min, &hint.triangle);
  return {t, tan_alpha_min, tan_alpha_max};
}

double estimate_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                                double alpha_min, double alpha_max) {
  if (apex.is_environment() || other.is_environment()) return alpha_max;
  const ConeTan cone = estimate_cone_tan(scene, apex, other, alpha_min, alpha_max);
  if (!(cone.t > cone.tan_min)) return alpha_min;
  return std::clamp(std::atan(cone.t), alpha_min, alpha_max);
}

double field_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                             double alpha_min, double alpha_max) {
  if (apex.is_environment() || other.is_environment()) return alpha_max;
  const DVec3 a(apex.position), b(other.position);
  const double length = glm::length(b - a);
  if (!(length > 0.0)) return alpha_min;
  const double tan_alpha_min = std::tan(alpha_min);
  const double s_lo = 1e-9 * length, s_hi = length * (1.0 - kConeEndMargin);
  const double s_a = kFieldEndFraction * length, s_b = s_hi - kFieldEndFraction * length;
  double t = tan_of_limit(alpha_max);
  if (s_b > s_a) {
    // Double rounding of the sample points and of the bound itself, far below a cell.
    const double scale = std::max({1.0, glm::length(a), glm::length(b)});
    if (!march_field(scene.clearance_field(), a, (b - a) / length, s_a, s_b, 1e-9 * scale,
                     tan_alpha_min, &t))
      return alpha_min;
    // The ends, where the endpoints' own surfaces come within a cell of the axis, exactly.
    t = walk_span(scene, apex, other, length, s_lo, s_a, t, tan_alpha_min);
    if (t > tan_alpha_min) t = walk_span(scene, apex, other, length, s_b, s_hi, t, tan_alpha_min);
  } else {
    t = walk_span(scene, apex, other, length, s_lo, s_hi, t, tan_alpha_min);
  }
  if (!(t > tan_alpha_min)) return alpha_min;
  return std::clamp(std::atan(t), alpha_min, alpha_max);
}

namespace {

struct CacheEntry {
  const Scene* scene = nullptr;
  ConeMethod method = ConeMethod::Exact;
  Vec3 apex{0.0f}, other{0.0f};
  double alpha_min = 0.0, alpha_max = 0.0, cell_fraction = 0.0, alpha = 0.0;
};

// Recent results of this thread: a chain's step needs the cones of x (proposed, and cached,
// one step earlier) and of y. Exact key comparison, so a hit returns the same bits as a
// recomputation: determinism does not depend on the cache, its replacement policy or thread
// scheduling. Direct-mapped by a hash of the key: a linear scan of the entries cost as much
// as a tenth of an estimate on every call.
struct ConeCache {
  static constexpr size_t kSize = 128;  // slot_of's range
  std::array<CacheEntry, kSize> entries;
};

}  // namespace

double cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                       double alpha_min, double alpha_max, ConeMethod method,
                       double cell_fraction) {
  if (apex.is_environment() || other.is_environment()) return alpha_max;
  thread_local ConeCache cache;
  CacheEntry& e = cache.entries[slot_of(apex.position, other.position, alpha_min, alpha_max)];
  if (e.scene == &scene && e.method == method && e.alpha_min == alpha_min &&
      e.alpha_max == alpha_max && e.cell_fraction == cell_fraction && same(e.apex, apex.position) &&
      same(e.other, other.position))
    return e.alpha;
  // The cell cones have their own table of quantised keys behind this one (which spares
  // computing a key for the cones of the chain's current state).
  const double alpha =
      method == ConeMethod::Field ? field_cone_half_angle(scene, apex, other, alpha_min, alpha_max)
      : method == ConeMethod::Cells
          ? cell_cone_half_angle(scene, apex, other, alpha_min, alpha_max, cell_fraction)
          : estimate_cone_half_angle(scene, apex, other, alpha_min, alpha_max);
  // (The cell cones may have used this slot meanwhile, for an exact cone they fell back on.)
  e = {&scene, method, apex.position, other.position, alpha_min, alpha_max, cell_fraction, alpha};
  return alpha;
}

}  // namespace emlt::geometry_aware
