#include "emlt/scene/surface_bvh.h"

#include <algorithm>
#include <limits>

namespace emlt {

void SurfaceBvh::add_mesh(uint32_t id, const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices) {
  if (meshes_.size() <= id) meshes_.resize(size_t(id) + 1);
  meshes_[id] = {positions.data(), indices.data()};
  for (uint32_t i = 0; 3 * size_t(i) < indices.size(); ++i) triangles_.push_back({id, i});
}

void SurfaceBvh::build() {
  const size_t n = triangles_.size();
  nodes_.clear();
  if (n == 0) return;
  // Indexed by the triangles' current positions in triangles_, which the build permutes
  // along with them.
  std::vector<Vec3> centroids(n);
  for (size_t i = 0; i < n; ++i) {
    const Corners c = corners(uint32_t(i));
    centroids[i] = (c.a + c.b + c.c) / 3.0f;
  }
  // A binary tree over n leaves-worth of triangles has under 2n nodes: reserved once, so
  // that the tree is never copied while it grows (the untouched rest costs address space,
  // not memory).
  std::vector<BinaryNode> binary;
  binary.reserve(2 * n);
  build_binary(0, uint32_t(n), centroids, binary);
  lower_ = binary[0].lower, upper_ = binary[0].upper;
  // A four-wide tree has at most as many nodes as the binary one has inner nodes.
  nodes_.reserve(binary.size() / 2 + 1);
  collapse(0, binary);
  nodes_.shrink_to_fit();
}

uint32_t SurfaceBvh::collapse(uint32_t binary_index, const std::vector<BinaryNode>& binary) {
  // The children: the binary node's two (or the node itself, a leaf at the root), then the
  // inner child with the largest box (half its area: the chance a search meets it) replaced
  // by its two while there is room.
  uint32_t children[kWidth] = {binary_index};
  int count = 1;
  if (binary[binary_index].count == 0)
    children[0] = binary_index + 1, children[1] = binary[binary_index].first, count = 2;
  while (count < kWidth) {
    int widest = -1;
    float widest_area = -1.0f;
    for (int i = 0; i < count; ++i) {
      const BinaryNode& child = binary[children[i]];
      if (child.count > 0) continue;
      const Vec3 e = child.upper - child.lower;
      const float area = e.x * e.y + e.y * e.z + e.z * e.x;
      if (area > widest_area) widest = i, widest_area = area;
    }
    if (widest < 0) break;
    const uint32_t opened = children[widest];
    children[widest] = opened + 1;
    children[count++] = binary[opened].first;
  }
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.emplace_back();
  for (int i = 0; i < kWidth; ++i) {
    Node& node = nodes_[index];  // (again after each child: the vector may have grown)
    if (i >= count) {
      for (int axis = 0; axis < 3; ++axis) {
        node.lower[axis][i] = std::numeric_limits<float>::infinity();
        node.upper[axis][i] = -std::numeric_limits<float>::infinity();
      }
      node.index[i] = 0, node.count[i] = 0;
      continue;
    }
    const BinaryNode& child = binary[children[i]];
    for (int axis = 0; axis < 3; ++axis)
      node.lower[axis][i] = child.lower[axis], node.upper[axis][i] = child.upper[axis];
    node.count[i] = child.count;
    node.index[i] = child.count > 0 ? child.first : 0;
    if (child.count == 0) {
      const uint32_t inner = collapse(children[i], binary);
      nodes_[index].index[i] = inner;
    }
  }
  return index;
}

uint32_t SurfaceBvh::build_binary(uint32_t begin, uint32_t end, std::vector<Vec3>& centroids,
                                  std::vector<BinaryNode>& binary) {
  const uint32_t index = uint32_t(binary.size());
  binary.emplace_back();
  Vec3 centre_lower(std::numeric_limits<float>::infinity()), centre_upper(-std::numeric_limits<float>::infinity());
  for (uint32_t i = begin; i < end; ++i) {
    centre_lower = glm::min(centre_lower, centroids[i]);
    centre_upper = glm::max(centre_upper, centroids[i]);
  }
  const Vec3 extent = centre_upper - centre_lower;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  if (end - begin <= kLeafSize || !(extent[axis] > 0.0f)) {
    Vec3 lower(std::numeric_limits<float>::infinity()), upper(-std::numeric_limits<float>::infinity());
    for (uint32_t i = begin; i < end; ++i) {
      const Corners c = corners(i);
      lower = glm::min(lower, glm::min(c.a, glm::min(c.b, c.c)));
      upper = glm::max(upper, glm::max(c.a, glm::max(c.b, c.c)));
    }
    binary[index] = {lower, begin, upper, end - begin};
    return index;
  }
  // The middle of the centroids' extent (a linear partition, cheaper than a median search),
  // or the median where that leaves one side empty or nearly so (also when the middle
  // rounds onto the lowest centroid, which would leave the lower side empty). Triangles and
  // centroids move together.
  const auto swap = [&](uint32_t i, uint32_t j) {
    std::swap(triangles_[i], triangles_[j]);
    std::swap(centroids[i], centroids[j]);
  };
  const float cut = 0.5f * (centre_lower[axis] + centre_upper[axis]);
  uint32_t middle = begin;
  for (uint32_t i = begin; i < end; ++i)
    if (centroids[i][axis] < cut) swap(i, middle++);
  if (middle == begin || middle == end || middle - begin < (end - begin) / 8 || end - middle < (end - begin) / 8) {
    // Sort a permutation and apply it: nth_element cannot move two arrays at once.
    middle = begin + (end - begin) / 2;
    std::vector<uint32_t> order(end - begin);
    for (uint32_t i = 0; i < end - begin; ++i) order[i] = begin + i;
    std::nth_element(order.begin(), order.begin() + (middle - begin), order.end(),
                     [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
    std::vector<TriangleRef> triangles(end - begin);
    std::vector<Vec3> moved(end - begin);
    for (uint32_t i = 0; i < end - begin; ++i) triangles[i] = triangles_[order[i]], moved[i] = centroids[order[i]];
    std::copy(triangles.begin(), triangles.end(), triangles_.begin() + begin);
    std::copy(moved.begin(), moved.end(), centroids.begin() + begin);
  }
  build_binary(begin, middle, centroids, binary);
  const uint32_t second = build_binary(middle, end, centroids, binary);
  // The node's box from its children's, each built already.
  const BinaryNode &left = binary[index + 1], &right = binary[second];
  binary[index] = {glm::min(left.lower, right.lower), second, glm::max(left.upper, right.upper), 0};
  return index;
}

}  // namespace emlt
