#include "emlt/core/sobol_points.h"

namespace emlt {

uint32_t van_der_corput_bits(uint32_t i) {
  // Reversing the index's 32 digits: the least significant becomes the first after the
  // binary point.
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
  i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
  i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
  return ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
}

uint32_t sobol_second_dimension_bits(uint32_t i) {
  // Column k of the generator matrix (the direction number of the index's digit k) is row k
  // of Pascal's triangle mod 2, placed from the first digit after the binary point.
  uint32_t bits = 0;
  for (uint32_t v = 1u << 31; i != 0; i >>= 1, v ^= v >> 1)
    if (i & 1u) bits ^= v;
  return bits;
}

std::vector<Vec2> sobol_square_points(uint32_t n, const DigitScramble& s) {
  std::vector<Vec2> points(n);
  for (uint32_t i = 0; i < n; ++i)
    points[i] = scrambled_point(van_der_corput_bits(i), sobol_second_dimension_bits(i), s);
  return points;
}

}  // namespace emlt
