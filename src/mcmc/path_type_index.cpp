#include "emlt/mcmc/path_type_index.h"

#include <algorithm>
#include <numeric>
#include <tuple>
#include <unordered_map>

#include "emlt/core/rng.h"
#include "emlt/mcmc/raster_order.h"

namespace emlt {

void PathTypeIndex::build(std::span<const PathType> types) {
  // An ensemble holds few distinct types: number them in order of first appearance, sort
  // the distinct types, then place the members by a counting sort, which keeps each group in
  // ensemble order. Linear in the ensemble size; sorting the members was a noticeable part
  // of a swap.
  std::unordered_map<PathType, uint32_t> first_seen;
  std::vector<PathType> distinct;
  std::vector<uint32_t> type_of(types.size());
  for (size_t i = 0; i < types.size(); ++i) {
    const auto [it, inserted] = first_seen.try_emplace(types[i], uint32_t(distinct.size()));
    if (inserted) distinct.push_back(types[i]);
    type_of[i] = it->second;
  }
  std::vector<uint32_t> order(distinct.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return std::tie(distinct[a].vertices, distinct[a].specular_mask) <
           std::tie(distinct[b].vertices, distinct[b].specular_mask);
  });
  std::vector<uint32_t> group_of(distinct.size());
  for (size_t g = 0; g < order.size(); ++g) group_of[order[g]] = uint32_t(g);

  std::vector<uint32_t> sizes(distinct.size(), 0);
  for (uint32_t t : type_of) ++sizes[group_of[t]];
  groups_.clear();
  std::vector<uint32_t> cursor(distinct.size());
  uint32_t begin = 0;
  for (size_t g = 0; g < order.size(); ++g) {
    const PathType& type = distinct[order[g]];
    groups_.push_back({type.specular_mask, type.vertices, begin, begin + sizes[g]});
    cursor[g] = begin;
    begin += sizes[g];
  }
  keys_.clear();
  members_.resize(types.size());
  for (size_t i = 0; i < types.size(); ++i) members_[cursor[group_of[type_of[i]]]++] = uint32_t(i);

  size_t slot_count = 2;
  while (slot_count < 2 * groups_.size()) slot_count *= 2;
  slots_.assign(slot_count, -1);
  for (size_t g = 0; g < groups_.size(); ++g) {
    size_t slot = slot_hash(groups_[g].mask, groups_[g].vertices) & (slot_count - 1);
    while (slots_[slot] >= 0) slot = (slot + 1) & (slot_count - 1);
    slots_[slot] = int32_t(g);
  }
}

uint64_t PathTypeIndex::slot_hash(uint64_t mask, uint8_t vertices) {
  return (mask * 0x9e3779b97f4a7c15ull ^ uint64_t(vertices) * 0xff51afd7ed558ccdull) >> 29;
}

const PathTypeIndex::Group* PathTypeIndex::find(const PathType& type) const {
  if (slots_.empty()) return nullptr;
  const size_t last = slots_.size() - 1;
  for (size_t slot = slot_hash(type.specular_mask, type.vertices) & last;;
       slot = (slot + 1) & last) {
    const int32_t g = slots_[slot];
    if (g < 0) return nullptr;
    const Group& group = groups_[size_t(g)];
    if (group.vertices == type.vertices && group.mask == type.specular_mask) return &group;
  }
}

std::span<const uint32_t> PathTypeIndex::members(const PathType& type) const {
  const Group* g = find(type);
  if (!g) return {};
  return std::span<const uint32_t>(members_.data() + g->begin, g->end - g->begin);
}

std::span<const uint32_t> PathTypeIndex::group_members(size_t group) const {
  const Group& g = groups_[group];
  return std::span<const uint32_t>(members_.data() + g.begin, g.end - g.begin);
}

PathType PathTypeIndex::group_type(size_t group) const {
  PathType type;
  type.vertices = groups_[group].vertices;
  type.specular_mask = groups_[group].mask;
  return type;
}

PathTypeIndex::Window PathTypeIndex::window(const PathType& type, uint64_t seed, uint64_t chain,
                                            uint64_t step, int m) const {
  const Group* g = find(type);
  if (!g || m <= 0) return {};
  const size_t size = g->end - g->begin;
  const uint64_t start = mix_bits(derive_stream_seed(seed, chain) ^ mix_bits(step)) % size;
  return {size_t(g - groups_.data()), size_t(start), std::min(size, size_t(m))};
}

void PathTypeIndex::order_by_raster(std::span<const Vec2> rasters, int width, int height) {
  width_ = width;
  height_ = height;
  std::vector<uint64_t> key_of(rasters.size());
  for (size_t i = 0; i < rasters.size(); ++i)
    key_of[i] = raster_order_key(rasters[i], width, height);
  for (const Group& g : groups_) {
    const auto begin = members_.begin() + g.begin, end = members_.begin() + g.end;
    std::sort(begin, end, [&](uint32_t a, uint32_t b) {
      return key_of[a] != key_of[b] ? key_of[a] < key_of[b] : a < b;
    });
  }
  keys_.resize(members_.size());
  for (size_t k = 0; k < members_.size(); ++k) keys_[k] = key_of[members_[k]];
}

PathTypeIndex::Window PathTypeIndex::nearby_window(const PathType& type, const Vec2& raster,
                                                   int m) const {
  const Group* g = find(type);
  if (!g || m <= 0 || keys_.empty()) return {};
  const size_t size = g->end - g->begin, count = std::min(size, size_t(m));
  const std::span<const uint64_t> keys(keys_.data() + g->begin, size);
  return {size_t(g - groups_.data()),
          centred_window_start(keys, raster_order_key(raster, width_, height_), count), count};
}

std::vector<uint32_t> PathTypeIndex::guides(const PathType& type, uint64_t seed, uint64_t chain,
                                            uint64_t step, int m) const {
  const Window w = window(type, seed, chain, step, m);
  std::vector<uint32_t> out;
  if (w.count == 0) return out;
  const std::span<const uint32_t> list = group_members(w.group);
  out.reserve(w.count);
  for (size_t i = 0; i < w.count; ++i) out.push_back(list[(w.start + i) % list.size()]);
  return out;
}

}  // namespace emlt
