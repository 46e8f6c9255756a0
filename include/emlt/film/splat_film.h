#pragma once
// Deterministic accumulation of splats: light-tracing contributions (BDPT's t = 1
// strategies, later MLT's path records) that land in pixels other than the one being
// rendered. Work is cut into fixed blocks whose number depends on the image only, never
// on the thread count; each block appends its splats, in the order it makes them, to its
// own SplatList, and after a pass the film adds the lists in block order. The sums are
// therefore the same bits at any thread count, without atomics.
#include <cstdint>
#include <span>
#include <vector>

#include "emlt/core/math.h"
#include "emlt/core/state_io.h"

namespace emlt {

struct SplatRecord {
  uint32_t pixel = 0;
  int32_t layer = -1;  // an extra layer (e.g. a BDPT strategy image) also receiving it; -1: none
  Rgb value{0.0f};
};

struct SplatList {
  std::vector<SplatRecord> records;
  void add(uint32_t pixel, const Rgb& value, int layer = -1) {
    records.push_back({pixel, layer, value});
  }
  void clear() { records.clear(); }
};

class SplatFilm {
 public:
  SplatFilm(int width, int height, int extra_layers = 0);

  // Adds the lists in index order (call once per pass, from one thread).
  void add_in_order(std::span<const SplatList> lists);

  const std::vector<DVec3>& sums() const { return sums_; }
  const std::vector<DVec3>& layer(int i) const { return layers_[size_t(i)]; }
  int layer_count() const { return int(layers_.size()); }

  // Checkpoints: the sums of every layer, exactly.
  void save(StateWriter& out) const;
  void load(StateReader& in);  // throws StateError for a film of another size

 private:
  std::vector<DVec3> sums_;
  std::vector<std::vector<DVec3>> layers_;
};

}  // namespace emlt
