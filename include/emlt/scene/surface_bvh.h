#pragma once
// A plain bounding-volume hierarchy over the scene's triangles, with its spheres listed
// beside it, for searches that Embree does not offer: Embree 3 traverses its own BVH only
// for rays and for balls (rtcPointQuery), and the geometry-aware cone
// (mutations/geometry_aware/cone.h) needs the surfaces within an angle of a segment. Covering
// a cone with balls visits everything in the balls, and a cone much thinner than its length
// is covered only by many balls or by balls much wider than the cone; on the public door
// (20,764 triangles) that was almost all of GAMLT's time. A traversal that tests the cone
// against each node itself opens only the nodes the cone meets.
//
// Layout: nodes in depth-first order, so an inner node's first child follows it and only the
// second child's index is stored; each leaf holds up to kLeafSize consecutive triangles of
// `corners` (three per triangle) and `ids` (more only where their centroids coincide). The
// split is the middle of the longest axis of the centroids' box, or their median where
// the middle leaves fewer than an eighth on one side: built in O(n log n) with no tuning
// (a third of a second for the public door's 382,628 triangles on the 2-core machine), at
// the first search, and the searches it serves are dominated by the few leaves near the
// segment.
#include <cstdint>
#include <vector>

#include "emlt/core/math.h"

namespace emlt {

class SurfaceBvh {
 public:
  static constexpr uint32_t kLeafSize = 4;

  struct Node {
    Vec3 lower;
    uint32_t first = 0;  // leaf: its first triangle; inner: the second child's node index
    Vec3 upper;
    uint32_t count = 0;  // leaf: its number of triangles (> 0); inner: 0
  };
  struct Sphere {
    Vec3 center;
    float radius = 0.0f;
  };

  // Adds a triangle; `id` is the caller's (Scene: geometry id << 32 | primitive id).
  void add_triangle(uint64_t id, const Vec3& a, const Vec3& b, const Vec3& c);
  void add_sphere(const Vec3& center, float radius) { spheres_.push_back({center, radius}); }
  // Builds the hierarchy over the triangles added; call once, after the last add.
  void build();

  const std::vector<Node>& nodes() const { return nodes_; }  // nodes()[0] is the root, if any
  const Vec3* corners(uint32_t triangle) const { return &corners_[3 * size_t(triangle)]; }
  uint64_t id(uint32_t triangle) const { return ids_[triangle]; }
  const std::vector<Sphere>& spheres() const { return spheres_; }

 private:
  uint32_t build_node(uint32_t begin, uint32_t end, std::vector<uint32_t>& order,
                      const std::vector<Vec3>& centroids);

  std::vector<Node> nodes_;
  std::vector<Vec3> corners_;
  std::vector<uint64_t> ids_;
  std::vector<Sphere> spheres_;
};

}  // namespace emlt
