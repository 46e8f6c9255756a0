#include "emlt/scene/surface_bvh.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace emlt {

void SurfaceBvh::add_triangle(uint64_t id, const Vec3& a, const Vec3& b, const Vec3& c) {
  corners_.insert(corners_.end(), {a, b, c});
  ids_.push_back(id);
}

void SurfaceBvh::build() {
  const size_t n = ids_.size();
  nodes_.clear();
  if (n == 0) return;
  std::vector<Vec3> centroids(n);
  for (size_t i = 0; i < n; ++i) centroids[i] = (corners_[3 * i] + corners_[3 * i + 1] + corners_[3 * i + 2]) / 3.0f;
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  nodes_.reserve(2 * (n / kLeafSize + 1));
  build_node(0, uint32_t(n), order, centroids);
  // The triangles in leaf order, so that a leaf reads one contiguous block.
  std::vector<Vec3> corners(corners_.size());
  std::vector<uint64_t> ids(n);
  for (size_t i = 0; i < n; ++i) {
    std::copy_n(&corners_[3 * size_t(order[i])], 3, &corners[3 * i]);
    ids[i] = ids_[order[i]];
  }
  corners_ = std::move(corners);
  ids_ = std::move(ids);
}

uint32_t SurfaceBvh::build_node(uint32_t begin, uint32_t end, std::vector<uint32_t>& order,
                                const std::vector<Vec3>& centroids) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.emplace_back();
  Vec3 centre_lower(std::numeric_limits<float>::infinity()), centre_upper(-std::numeric_limits<float>::infinity());
  for (uint32_t i = begin; i < end; ++i) {
    centre_lower = glm::min(centre_lower, centroids[order[i]]);
    centre_upper = glm::max(centre_upper, centroids[order[i]]);
  }
  const Vec3 extent = centre_upper - centre_lower;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  if (end - begin <= kLeafSize || !(extent[axis] > 0.0f)) {
    Vec3 lower(std::numeric_limits<float>::infinity()), upper(-std::numeric_limits<float>::infinity());
    for (uint32_t i = begin; i < end; ++i) {
      const Vec3* c = &corners_[3 * size_t(order[i])];
      for (int k = 0; k < 3; ++k) lower = glm::min(lower, c[k]), upper = glm::max(upper, c[k]);
    }
    nodes_[index] = {lower, begin, upper, end - begin};
    return index;
  }
  // The middle of the centroids' extent (a linear partition, cheaper than a median search),
  // or the median where that leaves one side empty or nearly so.
  const float cut = 0.5f * (centre_lower[axis] + centre_upper[axis]);
  uint32_t middle = uint32_t(
      std::partition(order.begin() + begin, order.begin() + end, [&](uint32_t t) { return centroids[t][axis] < cut; }) -
      order.begin());
  if (middle - begin < (end - begin) / 8 || end - middle < (end - begin) / 8) {
    middle = begin + (end - begin) / 2;
    std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end,
                     [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  }
  build_node(begin, middle, order, centroids);
  const uint32_t second = build_node(middle, end, order, centroids);
  // The node's box from its children's, each built already.
  const Node &left = nodes_[index + 1], &right = nodes_[second];
  nodes_[index] = {glm::min(left.lower, right.lower), second, glm::max(left.upper, right.upper), 0};
  return index;
}

}  // namespace emlt
