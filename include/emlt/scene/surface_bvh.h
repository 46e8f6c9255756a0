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
// Layout: each node holds up to kWidth = 4 children's boxes side by side, one array of four
// per bound and axis, so that a search tests the four at once in SIMD lanes (the cone's
// walk, in float with a margin); the children are inner nodes or leaves, and each leaf holds
// up to kLeafSize consecutive entries of `triangles` (more only where their centroids
// coincide), each naming a mesh and a triangle in it. The corners are read from the meshes'
// own arrays (Scene's geometry), not copied: on the 1,015,296-triangle terrain a copy put
// 100 MB on gamlt's peak memory. The tree is first built binary, split at the middle of the
// longest axis of the centroids' box, or their median where the middle leaves fewer than an
// eighth on one side: built in O(n log n) with no tuning (a third of a second for the public
// door's 382,628 triangles on the 2-core machine); then each node takes its grandchildren
// in place of its children, the largest child opened first, until it has four. A binary
// walk tested two children per step in double precision, about 57 instructions a test, and
// that was most of GAMLT's time on the public door (docs/performance.md). The searches it
// serves are dominated by the few leaves near the segment.
#include <cstdint>
#include <vector>

#include "emlt/core/math.h"

namespace emlt {

class SurfaceBvh {
 public:
  static constexpr uint32_t kLeafSize = 4;
  static constexpr int kWidth = 4;

  // Four children, lane by lane: child i's box is lower[axis][i] .. upper[axis][i]. A leaf
  // child has count[i] > 0 triangles from index[i]; an inner child has count[i] = 0 and
  // index[i] its node. An unused lane has count 0 and an empty box (lower +inf, upper -inf),
  // which no test can find meeting anything.
  struct alignas(64) Node {
    float lower[3][kWidth], upper[3][kWidth];
    uint32_t index[kWidth];
    uint32_t count[kWidth];
    bool used(int i) const { return lower[0][i] <= upper[0][i]; }
  };
  struct Sphere {
    Vec3 center;
    float radius = 0.0f;
  };

  // Adds mesh `id`'s triangles (indices: three per triangle, into positions). The arrays
  // are read, not copied: they must outlive the hierarchy, unchanged.
  void add_mesh(uint32_t id, const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices);
  void add_sphere(const Vec3& center, float radius) { spheres_.push_back({center, radius}); }
  // Builds the hierarchy over the meshes added; call once, after the last add.
  void build();

  // nodes()[0] is the root, if any triangle was added (its lanes may all be leaves).
  const std::vector<Node>& nodes() const { return nodes_; }
  // The box around every triangle (empty without triangles).
  Vec3 lower() const { return lower_; }
  Vec3 upper() const { return upper_; }
  // The i-th triangle in leaf order: its corners, and its id (mesh id << 32 | triangle index).
  struct Corners {
    const Vec3 &a, &b, &c;
  };
  Corners corners(uint32_t i) const {
    const Mesh& mesh = meshes_[triangles_[i].mesh];
    const uint32_t* index = mesh.indices + 3 * size_t(triangles_[i].triangle);
    return {mesh.positions[index[0]], mesh.positions[index[1]], mesh.positions[index[2]]};
  }
  uint32_t triangle_count() const { return uint32_t(triangles_.size()); }
  uint64_t id(uint32_t i) const { return (uint64_t(triangles_[i].mesh) << 32) | triangles_[i].triangle; }
  const std::vector<Sphere>& spheres() const { return spheres_; }

 private:
  struct Mesh {
    const Vec3* positions = nullptr;
    const uint32_t* indices = nullptr;
  };
  struct TriangleRef {
    uint32_t mesh, triangle;
  };
  // The binary tree the build makes first: depth-first, an inner node's first child right
  // after it, `first` the second child's index (inner) or the first triangle (leaf).
  struct BinaryNode {
    Vec3 lower;
    uint32_t first = 0;
    Vec3 upper;
    uint32_t count = 0;  // leaf: its number of triangles (> 0); inner: 0
  };

  uint32_t build_binary(uint32_t begin, uint32_t end, std::vector<Vec3>& centroids,
                        std::vector<BinaryNode>& binary);
  uint32_t collapse(uint32_t binary_index, const std::vector<BinaryNode>& binary);

  std::vector<Node> nodes_;
  Vec3 lower_{0.0f}, upper_{0.0f};
  std::vector<Mesh> meshes_;  // by mesh id (an id without triangles has no arrays)
  std::vector<TriangleRef> triangles_;
  std::vector<Sphere> spheres_;
};

}  // namespace emlt
