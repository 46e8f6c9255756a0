#include "emlt/scene/direct_triangles.h"

#include <bit>  // std::countr_zero
#include <cstring>
#include <utility>

// The helpers below pass eight-float vectors by value; they are internal to this file and
// inlined, so GCC's note that such an ABI differs with and without AVX concerns no caller.
#pragma GCC diagnostic ignored "-Wpsabi"

// The test runs only where the CPU has AVX2 (DirectTriangles::available), compiled for it
// whatever the build's baseline: eight lanes of the baseline's SSE spilled half their
// registers and ran at half Embree's rate. No FMA: a contracted a*b - c*d is not the exact
// negation of c*d - a*b, and the watertightness rests on the edge function of a shared
// edge being the same number, negated, in both triangles (CMakeLists.txt also compiles
// this file with -ffp-contract=off).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define EMLT_DIRECT_TRIANGLES 1
#define EMLT_SIMD_TARGET __attribute__((target("avx2")))
#include <immintrin.h>
#else
#define EMLT_DIRECT_TRIANGLES 0
#define EMLT_SIMD_TARGET
#endif

namespace emlt {
namespace {

// GCC's vector extensions (clang has them too): eight lanes of plain IEEE arithmetic, each
// rounded exactly as the scalar operation would be.
using Floats = float __attribute__((vector_size(4 * DirectTriangles::kLanes)));
using Mask = int32_t __attribute__((vector_size(4 * DirectTriangles::kLanes)));

[[gnu::always_inline]] EMLT_SIMD_TARGET inline Floats load(const float* p) {
  Floats v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

[[gnu::always_inline]] EMLT_SIMD_TARGET inline Floats splat(float x) {
  return Floats{} + x;
}

// One bit per lane whose mask is set (lane 0 in bit 0).
[[gnu::always_inline]] EMLT_SIMD_TARGET inline unsigned lane_bits(Mask m) {
#if EMLT_DIRECT_TRIANGLES
  return unsigned(_mm256_movemask_ps(__builtin_bit_cast(__m256, m)));
#else
  unsigned bits = 0;
  for (int lane = 0; lane < DirectTriangles::kLanes; ++lane) bits |= unsigned(m[lane] != 0) << lane;
  return bits;
#endif
}

}  // namespace

void DirectTriangles::add(uint32_t geometry, uint32_t primitive, const Vec3& p0, const Vec3& p1,
                          const Vec3& p2) {
  const size_t lane = count_ % kLanes;
  if (lane == 0) blocks_.push_back(Block{});  // zero-filled: degenerate triangles at the origin
  Block& block = blocks_.back();
  const Vec3* vertices[3] = {&p0, &p1, &p2};
  for (int vertex = 0; vertex < 3; ++vertex)
    for (int axis = 0; axis < 3; ++axis) block.p[vertex][axis][lane] = (*vertices[vertex])[axis];
  block.geometry[lane] = geometry;
  block.primitive[lane] = primitive;
  ++count_;
}

bool DirectTriangles::available() {
#if EMLT_DIRECT_TRIANGLES
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

template <bool kAnyHit>
EMLT_SIMD_TARGET bool DirectTriangles::trace(const Ray& ray, float tfar,
                                             DirectTriangleHit* hit) const {
  // The shear that takes the ray to the +z axis from its origin; z is the direction's
  // largest component, and x, y swap when it is negative so that the winding (the sign of
  // the determinant) is kept.
  const Vec3& d = ray.direction;
  const Vec3 magnitude = glm::abs(d);
  int kz = magnitude.x > magnitude.y ? (magnitude.x > magnitude.z ? 0 : 2)
                                     : (magnitude.y > magnitude.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
  if (d[kz] < 0.0f) std::swap(kx, ky);
  const Floats shear_x = splat(d[kx] / d[kz]), shear_y = splat(d[ky] / d[kz]);
  const Floats shear_z = splat(1.0f / d[kz]);
  const Floats origin_x = splat(ray.origin[kx]), origin_y = splat(ray.origin[ky]);
  const Floats origin_z = splat(ray.origin[kz]);
  const Floats tmin = splat(ray.tmin);

  // The nearest hit so far: its block and lane, and its edge functions and determinant, so
  // that the divisions for t, u and v are done once, for it alone.
  const Block* best = nullptr;
  int best_lane = 0;
  float best_t = tfar, best_e1 = 0.0f, best_e2 = 0.0f, best_det = 1.0f;
  for (const Block& block : blocks_) {
    Floats x[3], y[3], z[3];
    for (int vertex = 0; vertex < 3; ++vertex) {
      z[vertex] = load(block.p[vertex][kz]) - origin_z;
      x[vertex] = (load(block.p[vertex][kx]) - origin_x) - shear_x * z[vertex];
      y[vertex] = (load(block.p[vertex][ky]) - origin_y) - shear_y * z[vertex];
    }
    // Edge functions: each is the barycentric weight, times the determinant, of the vertex
    // opposite its edge. A point is inside when none is negative or none is positive.
    const Floats e0 = x[2] * y[1] - y[2] * x[1];
    const Floats e1 = x[0] * y[2] - y[0] * x[2];
    const Floats e2 = x[1] * y[0] - y[1] * x[0];
    const Floats zero{};
    const Mask outside =
        ((e0 < zero) | (e1 < zero) | (e2 < zero)) & ((e0 > zero) | (e1 > zero) | (e2 > zero));
    const Floats det = e0 + e1 + e2;
    // t = scaled / det, compared with tmin and tfar without dividing: where det < 0 (a
    // triangle seen from its back) both signs are flipped, which leaves t as it is.
    const Floats scaled = (e0 * z[0] + e1 * z[1] + e2 * z[2]) * shear_z;
    const Mask sign_bit = Mask{} + __builtin_bit_cast(int32_t, 0x80000000u);
    const Mask det_sign = __builtin_bit_cast(Mask, det) & sign_bit;
    const Floats abs_det = __builtin_bit_cast(Floats, __builtin_bit_cast(Mask, det) ^ det_sign);
    const Floats signed_scaled =
        __builtin_bit_cast(Floats, __builtin_bit_cast(Mask, scaled) ^ det_sign);
    // det == 0 (a degenerate or edge-on triangle, or padding) means all three edge
    // functions are 0 for a point not outside, so scaled is 0 and fails the first test.
    const Mask valid =
        ~outside & (signed_scaled > tmin * abs_det) & (signed_scaled <= splat(best_t) * abs_det);
    if constexpr (kAnyHit) {
      if (lane_bits(valid) != 0) return true;
      continue;
    }
    if (lane_bits(valid) == 0) continue;
    // Within (tmin, tfar] and, after the first hit, strictly nearer (ties keep the triangle
    // listed first); the comparisons above, made without dividing, can differ from these
    // by a rounding.
    const Floats t = signed_scaled / abs_det;
    const Mask nearer = best ? t < splat(best_t) : t <= splat(best_t);
    for (unsigned bits = lane_bits(valid & (t > tmin) & nearer); bits != 0; bits &= bits - 1) {
      const int lane = std::countr_zero(bits);
      if (best && !(t[lane] < best_t)) continue;
      best = &block, best_lane = lane, best_t = t[lane];
      best_e1 = e1[lane], best_e2 = e2[lane], best_det = det[lane];
    }
  }
  if constexpr (kAnyHit) return false;
  if (!best) return false;
  hit->t = best_t;
  hit->u = best_e1 / best_det;
  hit->v = best_e2 / best_det;
  hit->geometry = best->geometry[best_lane];
  hit->primitive = best->primitive[best_lane];
  return true;
}

bool DirectTriangles::nearest(const Ray& ray, float* tfar, DirectTriangleHit* hit) const {
  if (!trace<false>(ray, *tfar, hit)) return false;
  *tfar = hit->t;
  return true;
}

bool DirectTriangles::any(const Ray& ray) const {
  return trace<true>(ray, ray.tmax, nullptr);
}

}  // namespace emlt
