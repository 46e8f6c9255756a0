#pragma once
// The first n points of Sobol's (0,2)-sequence in the unit square, randomised by random
// digit scrambling (digit_scramble.h) so that estimators built on them stay unbiased.
//
// Its first dimension is the base-2 van der Corput sequence (digits of the index reversed),
// its second Sobol's second dimension, whose generator matrix is Pascal's triangle mod 2
// (direction numbers v_k = v_{k-1} XOR v_{k-1} >> 1 from v_0 = 1/2). Every block of 2^m
// consecutive points starting at a multiple of 2^m is a (0,m,2)-net: each elementary
// interval [a/2^j, (a+1)/2^j) x [b/2^(m-j), (b+1)/2^(m-j)) holds exactly one point. At
// other n the first n points are a union of such nets of decreasing size.
#include <cstdint>
#include <vector>

#include "emlt/core/digit_scramble.h"

namespace emlt {

// The 32 digits of point i's coordinates, unscrambled.
uint32_t van_der_corput_bits(uint32_t i);
uint32_t sobol_second_dimension_bits(uint32_t i);

// The first n points, scrambled by s.
std::vector<Vec2> sobol_square_points(uint32_t n, const DigitScramble& s);

}  // namespace emlt
