#pragma once
// The clamped two-tailed geometric distribution P(i) proportional to 2^-|i - centre| on
// [low, high] (Mitsuba's choice for the bidirectional mutation's lengths): small changes
// are likely, any change within the range is possible.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "emlt/core/rng.h"

namespace emlt {

class TwoTailedGeometric {
 public:
  // The normalising sum in closed form: the bidirectional mutation builds four of these per
  // step, and a loop over the whole range was its largest single cost. The terms are
  // powers of two, so while the exponents lie within 51 of each other every partial sum of
  // the loop is exact and equals the closed form; beyond that the loop runs.
  TwoTailedGeometric(int centre, int low, int high) : centre_(centre), low_(low), high_(high) {
    if (high_ < low_) return;
    if (std::max(std::abs(low_ - centre_), std::abs(high_ - centre_)) <= 51) {
      // Σ_{n=a}^{b} 2^-n = 2^(1-a) - 2^-b on each side of the centre.
      const auto run = [](int a, int b) { return power_of_two(1 - a) - power_of_two(-b); };
      if (low_ <= centre_) total_ += run(centre_ - std::min(high_, centre_), centre_ - low_);
      if (high_ > centre_) total_ += run(std::max(low_, centre_ + 1) - centre_, high_ - centre_);
    } else {
      for (int i = low_; i <= high_; ++i) total_ += weight(i);
    }
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
  static double power_of_two(int e) { return std::bit_cast<double>(uint64_t(1023 + e) << 52); }
  double weight(int i) const {
    const int n = std::abs(i - centre_);
    return n < 1022 ? std::bit_cast<double>(uint64_t(1023 - n) << 52) : 0.0;
  }
  int centre_, low_, high_;
  double total_ = 0.0;
};

}  // namespace emlt
