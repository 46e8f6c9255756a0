#pragma once
// The clamped two-tailed geometric distribution P(i) proportional to 2^-|i - centre| on
// [low, high] (Mitsuba's choice for the bidirectional mutation's lengths): small changes
// are likely, any change within the range is possible.
#include <bit>
#include <cmath>
#include <cstdint>

#include "emlt/core/rng.h"

namespace emlt {

class TwoTailedGeometric {
 public:
  TwoTailedGeometric(int centre, int low, int high) : centre_(centre), low_(low), high_(high) {
    for (int i = low_; i <= high_; ++i) total_ += weight(i);
  }
  bool empty() const { return high_ < low_; }
  double pmf(int i) const { return i < low_ || i > high_ ? 0.0 : weight(i) / total_; }
  int sample(float u) const {
    double target = double(u) * total_;
    for (int i = low_; i < high_; ++i) {
      target -= weight(i);
      if (target < 0.0) return i;
    }
    return high_;
  }

 private:
  // 2^-|i - centre| built from its exponent bits: exact, and far cheaper than ldexp in the
  // mutation loop (it showed up in MLT profiles).
  double weight(int i) const {
    const int n = std::abs(i - centre_);
    return n < 1022 ? std::bit_cast<double>(uint64_t(1023 - n) << 52) : 0.0;
  }
  int centre_, low_, high_;
  double total_ = 0.0;
};

}  // namespace emlt
