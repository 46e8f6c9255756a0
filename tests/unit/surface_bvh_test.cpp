#include "emlt/scene/surface_bvh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>
#include <vector>

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
  // Lane i of node `n` holds p.
  const auto inside = [](const Vec3& p, const SurfaceBvh::Node& n, int i) {
    for (int axis = 0; axis < 3; ++axis)
      if (!(p[axis] >= n.lower[axis][i] && p[axis] <= n.upper[axis][i])) return false;
    return true;
  };
  const auto inside_box = [](const Vec3& p, const Vec3& lower, const Vec3& upper) {
    return glm::all(glm::greaterThanEqual(p, lower)) && glm::all(glm::lessThanEqual(p, upper));
  };
  // (node, the box of the lane that leads to it: the boxes of its ancestors are checked
  // through the recursion)
  std::vector<std::tuple<uint32_t, Vec3, Vec3>> stack{{0u, bvh.lower(), bvh.upper()}};
  size_t visited = 0;
  while (!stack.empty()) {
    const auto [index, lower, upper] = stack.back();
    stack.pop_back();
    ASSERT_LT(index, nodes.size());
    ++visited;
    const SurfaceBvh::Node& node = nodes[index];
    int used = 0;
    for (int i = 0; i < SurfaceBvh::kWidth; ++i) {
      if (!node.used(i)) {
        EXPECT_EQ(node.count[i], 0u);
        continue;
      }
      ++used;
      const Vec3 child_lower(node.lower[0][i], node.lower[1][i], node.lower[2][i]);
      const Vec3 child_upper(node.upper[0][i], node.upper[1][i], node.upper[2][i]);
      EXPECT_TRUE(inside_box(child_lower, lower, upper) && inside_box(child_upper, lower, upper));
      if (node.count[i] > 0) {
        for (uint32_t t = node.index[i]; t < node.index[i] + node.count[i]; ++t) {
          const SurfaceBvh::Corners c = bvh.corners(t);
          EXPECT_TRUE(inside(c.a, node, i) && inside(c.b, node, i) && inside(c.c, node, i));
          EXPECT_TRUE(seen.insert(bvh.id(t)).second);
        }
        continue;
      }
      stack.push_back({node.index[i], child_lower, child_upper});
    }
    EXPECT_GT(used, 0);
    // Every node stands for an inner node of the binary tree, so has two lanes or more; only
    // a root over a single leaf has one.
    if (index != 0) {
      EXPECT_GE(used, 2);
    }
  }
  EXPECT_EQ(visited, nodes.size());
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
