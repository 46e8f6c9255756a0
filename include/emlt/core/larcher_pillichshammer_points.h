#pragma once
// The Larcher-Pillichshammer (0,m,2)-net (Larcher and Pillichshammer, "Walsh series analysis
// of the L2-discrepancy of symmetrized point sets", 2001): x_i = i/n and y_i the radical
// inverse of i through the generator matrix whose every entry on or above the diagonal is 1
// (digit j of y is the XOR of the index's digits j-1, j, j+1, ... counting from 0), randomised
// by random digit scrambling (digit_scramble.h) so that estimators stay unbiased. Among the
// (0,m,2)-nets it has the lowest known star discrepancy, which is why [SF] compared it.
//
// At n = 2^m it is a (0,m,2)-net. At other n, x_i = i/n (its 32-digit binary fraction,
// rounded down) beside the same y_i: a Hammersley-like set, no longer a net, still
// marginally uniform once scrambled.
#include <cstdint>
#include <vector>

#include "emlt/core/digit_scramble.h"

namespace emlt {

// The 32 digits of y_i, unscrambled.
uint32_t larcher_pillichshammer_bits(uint32_t i);

// The n points, scrambled by s.
std::vector<Vec2> larcher_pillichshammer_square_points(uint32_t n, const DigitScramble& s);

}  // namespace emlt
