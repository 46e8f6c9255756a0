#include "emlt/scene/surface_bvh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "emlt/core/rng.h"

namespace emlt {
namespace {

// Every triangle in exactly one leaf, every node's box around everything below it, every
// leaf non-empty: what the cone's walk relies on (a triangle outside its leaf's box would
// be missed).
void expect_well_formed(const SurfaceBvh& bvh, size_t triangles) {
  const auto& nodes = bvh.nodes();
  ASSERT_FALSE(nodes.empty());
  std::set<uint64_t> seen;
  const auto inside = [](const Vec3& p, const SurfaceBvh::Node& n) {
    return glm::all(glm::greaterThanEqual(p, n.lower)) && glm::all(glm::lessThanEqual(p, n.upper));
  };
  // (node, the boxes of its ancestors are checked through the recursion)
  std::vector<std::pair<uint32_t, uint32_t>> stack{{0u, 0u}};
  while (!stack.empty()) {
    const auto [index, parent] = stack.back();
    stack.pop_back();
    const SurfaceBvh::Node& node = nodes[index];
    const SurfaceBvh::Node& up = nodes[parent];
    EXPECT_TRUE(inside(node.lower, up) && inside(node.upper, up));
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const SurfaceBvh::Corners c = bvh.corners(i);
        EXPECT_TRUE(inside(c.a, node) && inside(c.b, node) && inside(c.c, node));
        EXPECT_TRUE(seen.insert(bvh.id(i)).second);
      }
      continue;
    }
    ASSERT_LT(node.first, nodes.size());
    stack.push_back({index + 1, index});
    stack.push_back({node.first, index});
  }
  EXPECT_EQ(seen.size(), triangles);
}

TEST(SurfaceBvh, HoldsEveryTriangleOfRandomMeshes) {
  Rng rng(7, 0);
  std::vector<Vec3> positions;
  std::vector<uint32_t> indices;
  for (uint32_t i = 0; i < 3000; ++i) {
    const Vec3 centre(rng.uniform() * 10.0f, rng.uniform() * 10.0f, rng.uniform() * 0.1f);
    for (int k = 0; k < 3; ++k) {
      positions.push_back(centre + 0.1f * Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
      indices.push_back(uint32_t(positions.size() - 1));
    }
  }
  std::vector<Vec3> quad{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<uint32_t> quad_indices{0, 1, 2, 0, 2, 3};
  SurfaceBvh bvh;
  bvh.add_mesh(0, positions, indices);
  bvh.add_mesh(2, quad, quad_indices);  // a gap in the ids (a sphere's, in a scene)
  bvh.build();
  expect_well_formed(bvh, 3002);
}

// Centroids one float apart, the lower with an even last bit: the middle of their extent
// rounds onto the lower one, and a split there would leave an empty side (an empty leaf,
// read as an inner node).
TEST(SurfaceBvh, SplitsCentroidsOneFloatApart) {
  // Triangles whose corners share x: the centroid's x is (x + x + x) / 3 in float, as the
  // build computes it. Find two such triangles with adjacent centroid x.
  const auto centroid_x = [](float x) { return (x + x + x) / 3.0f; };
  float x_low = 1.0f, x_high = 1.0f;
  bool found = false;
  for (float x = 1.0f; x < 1.001f && !found; x = std::nextafter(x, 2.0f)) {
    const float c = centroid_x(x);
    const float c_next = std::nextafter(c, 2.0f);
    if (0.5f * (c + c_next) != c) continue;
    for (float y = std::nextafter(x, 2.0f); y < x + 1e-5f; y = std::nextafter(y, 2.0f))
      if (centroid_x(y) == c_next) {
        x_low = x, x_high = y, found = true;
        break;
      }
  }
  ASSERT_TRUE(found);
  std::vector<Vec3> positions;
  std::vector<uint32_t> indices;
  for (int t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k) {
      positions.push_back(Vec3(t == 0 ? x_low : x_high, float(k == 1), float(k == 2)));
      indices.push_back(uint32_t(positions.size() - 1));
    }
  SurfaceBvh bvh;
  bvh.add_mesh(0, positions, indices);
  bvh.build();
  expect_well_formed(bvh, 2);
  const std::vector<Vec3> pair = positions;
  for (int copies = 0; copies < 2; ++copies) positions.insert(positions.end(), pair.begin(), pair.end());
  indices.clear();
  for (uint32_t i = 0; i < positions.size(); ++i) indices.push_back(i);
  SurfaceBvh larger;  // more than a leaf, fewer than 8 (where the eighth rule would step in)
  larger.add_mesh(0, positions, indices);
  larger.build();
  expect_well_formed(larger, 6);
}

}  // namespace
}  // namespace emlt
