#pragma once
// EMLT's path-type tree: the paths of the frozen ensemble Y grouped by Heckbert type
// (length and which interior vertices are specular), rebuilt at every swap. A chain asks
// for Upsilon, the M guide paths of its current path's type, chosen one of two ways:
// - by a counter (the paper's §3.1.1 literally): M consecutive entries from an offset hashed
//   from (seed, chain, step), the same for x and for the proposal;
// - near the path (order_by_raster): each type's list sorted along a Hilbert curve over the
//   film, and the M entries centred on the current path's image point. Then Upsilon is a
//   function of the path, so the reverse move is evaluated against the proposal's own
//   Upsilon (the strategies in mutations/ensemble/ do so).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "emlt/core/math.h"
#include "emlt/path/path_type.h"

namespace emlt {

class PathTypeIndex {
 public:
  // Groups ensemble members by type; member i is types[i]. Deterministic: each group lists
  // its members in ensemble order.
  void build(std::span<const PathType> types);

  size_t type_count() const { return groups_.size(); }
  // The members (ensemble indices) of this type, in ensemble order; empty if none.
  std::span<const uint32_t> members(const PathType& type) const;
  // Up to m members of this type: m consecutive entries (cyclically) of the type's list,
  // starting at an offset hashed from (seed, chain, step). Fewer than m when the type has
  // fewer members.
  std::vector<uint32_t> guides(const PathType& type, uint64_t seed, uint64_t chain, uint64_t step,
                               int m) const;

  // Sorts each type's members along the Hilbert curve of their image points (rasters[i] of
  // member i; ties in ensemble order), for nearby_window. Deterministic.
  void order_by_raster(std::span<const Vec2> rasters, int width, int height);
  bool ordered_by_raster() const { return !keys_.empty(); }

  // The same choice without building the list: guides() is entries start, start + 1, ...
  // (cyclically) of group_members(group), `count` of them; count = 0 when there are none.
  struct Window {
    size_t group = 0;
    size_t start = 0;
    size_t count = 0;
  };
  Window window(const PathType& type, uint64_t seed, uint64_t chain, uint64_t step, int m) const;
  // After order_by_raster: the min(m, members) entries of this type centred on the curve
  // position of `raster` (never past the list's ends). A function of Y and (type, raster).
  Window nearby_window(const PathType& type, const Vec2& raster, int m) const;
  // Groups are numbered 0 .. type_count() - 1.
  std::span<const uint32_t> group_members(size_t group) const;
  PathType group_type(size_t group) const;

 private:
  struct Group {
    uint64_t mask = 0;
    uint8_t vertices = 0;
    uint32_t begin = 0, end = 0;  // range in members_
  };
  const Group* find(const PathType& type) const;
  static uint64_t slot_hash(uint64_t mask, uint8_t vertices);

  std::vector<uint32_t> members_;  // grouped by type
  std::vector<uint64_t> keys_;     // after order_by_raster: members_' curve positions
  int width_ = 0, height_ = 0;     // the film of those positions
  std::vector<Group> groups_;      // sorted by (vertices, mask)
  // Open addressing over the groups (index, or -1 for an empty slot; a power of two of them,
  // at most half full): every guided step looks its type up, and a binary search over the
  // groups cost as much as the rest of finding Υ (docs/experiments.md, "Cost per mutation").
  std::vector<int32_t> slots_;
};

}  // namespace emlt
