#pragma once
// A scene of a few dozen triangles (the Cornell boxes of the field) tested whole, eight
// triangles per step, in place of Embree's BVH. On such scenes the BVH does not pay: its
// leaves are large walls whose boxes every ray meets, and rtcIntersect1 spent about 1,000
// instructions per ray on the 24 triangles of scenes/cornell-glass, several times what
// testing every triangle costs (docs/performance.md, *Speed-ups*, "27 Nov:
// direct triangle tests on small scenes").
//
// The test is the watertight one of Woop, Benthin and Wald (JCGT 2013): the ray is sheared
// onto the z axis once, then each triangle's three edge functions are evaluated in its
// frame. Two triangles that share an edge share its vertices exactly, so the edge function
// of a point on that edge is the same number for both and no ray slips between them. A
// point exactly on an edge counts for both triangles (the nearer, or the first, is kept).
#include <cstdint>
#include <vector>

#include "emlt/core/math.h"
#include "emlt/scene/ray.h"

namespace emlt {

struct DirectTriangleHit {
  float t = 0.0f;
  // Embree's convention: the point is (1 - u - v) p0 + u p1 + v p2.
  float u = 0.0f, v = 0.0f;
  uint32_t geometry = 0, primitive = 0;
};

class DirectTriangles {
 public:
  // Up to this many triangles are tested directly (Scene::build falls back on the BVH
  // above it, and for alpha-masked meshes, whose filter needs Embree).
  static constexpr size_t kMaxTriangles = 64;
  // Triangles per step: one AVX register of floats.
  static constexpr int kLanes = 8;

  // Whether this CPU runs the test (it is compiled for AVX2); where it does not, Scene
  // keeps every triangle in the BVH.
  static bool available();

  void add(uint32_t geometry, uint32_t primitive, const Vec3& p0, const Vec3& p1, const Vec3& p2);
  size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }

  // The nearest triangle with tmin < t <= *tfar: fills *hit, sets *tfar = hit->t.
  bool nearest(const Ray& ray, float* tfar, DirectTriangleHit* hit) const;
  // Whether any triangle lies on the open segment tmin < t <= ray.tmax.
  bool any(const Ray& ray) const;

 private:
  // kLanes triangles, structure of arrays: p[vertex][axis][lane]. Lanes past the last
  // triangle repeat a triangle of zero area, which no ray hits (its determinant is 0).
  struct Block {
    alignas(32) float p[3][3][kLanes];
    uint32_t geometry[kLanes], primitive[kLanes];
  };
  template <bool kAnyHit>
  bool trace(const Ray& ray, float tfar, DirectTriangleHit* hit) const;

  std::vector<Block> blocks_;
  size_t count_ = 0;
};

}  // namespace emlt
