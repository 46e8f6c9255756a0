#pragma once
// A spatially coherent order of points on the image plane, for EMLT's local Υ: the guides of
// a step are a window of consecutive entries of its path type's list sorted along a Hilbert
// curve over the film, centred where the current path's image point falls. Consecutive
// entries of a Hilbert order are neighbours on the plane (a Morton order jumps across the
// image at every power-of-two boundary), so such a window is a compact patch of guides
// around the current path.
#include <cstddef>
#include <cstdint>
#include <span>

#include "emlt/core/math.h"

namespace emlt {

// Cells per side of the curve's grid: 2^16, finer than any film's pixels.
inline constexpr int kRasterOrderBits = 16;

// Position along the Hilbert curve of order `bits` of cell (x, y), 0 <= x, y < 2^bits.
uint64_t hilbert_index(uint32_t x, uint32_t y, int bits = kRasterOrderBits);

// The curve position of a raster point of a width x height film: the film is laid in a
// square of side max(width, height) so that the curve's cells are square; points off the
// film are clamped to its edge.
uint64_t raster_order_key(const Vec2& raster, int width, int height);

// The first entry of the window of `count` consecutive entries of `sorted_keys` (ascending)
// centred on where `key` would be inserted, shifted to stay inside the list: entries
// [start, start + min(count, size)). A function of the list and the key alone.
size_t centred_window_start(std::span<const uint64_t> sorted_keys, uint64_t key, size_t count);

}  // namespace emlt
