#pragma once
// Random digit scrambling of base-2 point sets (Kollig and Keller, "Efficient
// multidimensional sampling", 2002): every coordinate's 32 binary digits are XORed with one
// random 32-bit word per coordinate, the same word for every point of a set.
//
// Why this and not Owen's nested scrambling: it is the scrambling the spherical Fibonacci
// paper applied to its Sobol and Larcher-Pillichshammer sets ([SF] Tab. 1), and it keeps
// what the estimator needs. XOR with a fixed word permutes the elementary intervals of
// every shape among themselves, so a (0,m,2)-net stays one; XOR with a uniform random word
// makes any fixed word uniform, so every scrambled point is marginally uniform in the square
// and an estimator averaging f over the points is unbiased. Owen's scrambling also
// randomises the digits below each one independently (better variance on smooth
// integrands); it is not what the paper compared.
#include <cstdint>

#include "emlt/core/math.h"
#include "emlt/core/rng.h"

namespace emlt {

struct DigitScramble {
  uint32_t x = 0, y = 0;
  static DigitScramble draw(Rng& rng) {
    const uint32_t a = rng.next_u32();
    return {a, rng.next_u32()};
  }
};

// The top 24 digits of a 32-digit binary fraction as a float in [0, 1): exact, never 1.
inline float binary_fraction(uint32_t bits) {
  return float(bits >> 8) * 0x1p-24f;
}

// A point given by its two coordinates' 32 binary digits, scrambled.
inline Vec2 scrambled_point(uint32_t x_bits, uint32_t y_bits, const DigitScramble& s) {
  return {binary_fraction(x_bits ^ s.x), binary_fraction(y_bits ^ s.y)};
}

}  // namespace emlt
