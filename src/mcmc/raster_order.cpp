#include "emlt/mcmc/raster_order.h"

#include <algorithm>
#include <cmath>

namespace emlt {

uint64_t hilbert_index(uint32_t x, uint32_t y, int bits) {
  // Walk down the quadrant tree from the coarsest level: at each level the quadrant adds its
  // rank along the curve (0-3, times the cells below it), and the coordinates are turned
  // into the frame of the curve's sub-square there (a transpose for the first quadrant, a
  // transpose with a flip for the last) so that the next level sees the standard curve.
  uint64_t index = 0;
  for (uint32_t half = uint32_t(1) << (bits - 1); half > 0; half >>= 1) {
    const uint32_t right = (x & half) ? 1u : 0u, top = (y & half) ? 1u : 0u;
    index += uint64_t(half) * uint64_t(half) * uint64_t((3u * right) ^ top);
    if (top == 0) {
      if (right == 1) {
        x = half - 1 - (x & (half - 1));
        y = half - 1 - (y & (half - 1));
      }
      std::swap(x, y);
    }
    x &= half - 1;
    y &= half - 1;
  }
  return index;
}

uint64_t raster_order_key(const Vec2& raster, int width, int height) {
  const double side = double(std::max(std::max(width, height), 1));
  const double cells = double(uint32_t(1) << kRasterOrderBits);
  const auto cell = [&](float coordinate) {
    const double c = std::floor(double(coordinate) / side * cells);
    return uint32_t(std::clamp(std::isfinite(c) ? c : 0.0, 0.0, cells - 1.0));
  };
  return hilbert_index(cell(raster.x), cell(raster.y));
}

size_t centred_window_start(std::span<const uint64_t> sorted_keys, uint64_t key, size_t count) {
  const size_t size = sorted_keys.size();
  if (count >= size) return 0;
  const size_t position =
      size_t(std::lower_bound(sorted_keys.begin(), sorted_keys.end(), key) - sorted_keys.begin());
  return std::min(position - std::min(position, count / 2), size - count);
}

}  // namespace emlt
