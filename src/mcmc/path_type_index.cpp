#include "emlt/mcmc/path_type_index.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <tuple>

#include "emlt/core/rng.h"

namespace emlt {

namespace {
struct Keyed {
  uint8_t vertices;
  uint64_t mask;
  uint32_t member;
  bool operator<(const Keyed& o) const {
    return std::tie(vertices, mask, member) < std::tie(o.vertices, o.mask, o.member);
  }
};
}  // namespace

void PathTypeIndex::build(std::span<const PathType> types) {
  std::vector<Keyed> keyed(types.size());
  for (size_t i = 0; i < types.size(); ++i)
    keyed[i] = {types[i].vertices, types[i].specular_mask, uint32_t(i)};
  // The member index breaks ties, so the order (and each group's list) is unique.
  tbb::parallel_sort(keyed.begin(), keyed.end());
  members_.resize(keyed.size());
  groups_.clear();
  for (size_t i = 0; i < keyed.size(); ++i) {
    members_[i] = keyed[i].member;
    if (groups_.empty() || groups_.back().vertices != keyed[i].vertices || groups_.back().mask != keyed[i].mask)
      groups_.push_back({keyed[i].mask, keyed[i].vertices, uint32_t(i), uint32_t(i)});
    groups_.back().end = uint32_t(i + 1);
  }
}

const PathTypeIndex::Group* PathTypeIndex::find(const PathType& type) const {
  const auto it = std::lower_bound(groups_.begin(), groups_.end(), type, [](const Group& g, const PathType& t) {
    return std::tie(g.vertices, g.mask) < std::tie(t.vertices, t.specular_mask);
  });
  if (it == groups_.end() || it->vertices != type.vertices || it->mask != type.specular_mask) return nullptr;
  return &*it;
}

std::span<const uint32_t> PathTypeIndex::members(const PathType& type) const {
  const Group* g = find(type);
  if (!g) return {};
  return std::span<const uint32_t>(members_.data() + g->begin, g->end - g->begin);
}

std::vector<uint32_t> PathTypeIndex::guides(const PathType& type, uint64_t seed, uint64_t chain,
                                            uint64_t step, int m) const {
  const std::span<const uint32_t> list = members(type);
  std::vector<uint32_t> out;
  if (list.empty() || m <= 0) return out;
  const size_t count = std::min(list.size(), size_t(m));
  const uint64_t start = mix_bits(derive_stream_seed(seed, chain) ^ mix_bits(step)) % list.size();
  out.reserve(count);
  for (size_t i = 0; i < count; ++i) out.push_back(list[(start + i) % list.size()]);
  return out;
}

}  // namespace emlt
