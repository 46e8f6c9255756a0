#include "emlt/core/larcher_pillichshammer_points.h"

namespace emlt {

uint32_t larcher_pillichshammer_bits(uint32_t i) {
  // Column k of the generator matrix (for the index's digit k) has ones in rows 1 .. k+1:
  // the first k+1 digits after the binary point.
  uint32_t bits = 0;
  for (uint32_t column = 1u << 31; i != 0; i >>= 1, column |= column >> 1)
    if (i & 1u) bits ^= column;
  return bits;
}

std::vector<Vec2> larcher_pillichshammer_square_points(uint32_t n, const DigitScramble& s) {
  std::vector<Vec2> points(n);
  for (uint32_t i = 0; i < n; ++i) {
    const auto x_bits = uint32_t((uint64_t(i) << 32) / n);  // i/n in 32 binary digits
    points[i] = scrambled_point(x_bits, larcher_pillichshammer_bits(i), s);
  }
  return points;
}

}  // namespace emlt
