#pragma once
// Running figures of independent samples whose mean is a normalisation b: path-space MLT's
// bootstrap and the samples drawn beside its chains (normalisation_pass.h), and the primary
// samples of pssmlt and mmlt (pss_normalisation.h). Sums of doubles: whoever adds them fixes
// the order, so that the same samples give the same bits.
#include <cstdint>

namespace emlt {

struct NormalisationSums {
  uint64_t samples = 0;
  double sum = 0.0, sum_squares = 0.0;
  double largest = 0.0;  // the largest single sample

  void add(double x) {
    ++samples;
    sum += x;
    sum_squares += x * x;
    if (x > largest) largest = x;
  }
  // Another set's samples, as if added after this one's.
  void add(const NormalisationSums& other) {
    samples += other.samples;
    sum += other.sum;
    sum_squares += other.sum_squares;
    if (other.largest > largest) largest = other.largest;
  }

  double b() const { return samples > 0 ? sum / double(samples) : 0.0; }
  // The standard error of b from the samples' spread.
  double standard_error() const;
  // The error printed with b: the standard error widened by the largest sample over the
  // count, as if one more path that bright had come. Where rare, bright paths carry much of
  // b (caustics through glass) the samples' spread understates b's until such paths have
  // been met many times: on the caustic pool with 200,000 samples the mean z^2 over seeds
  // was 5.3 with the plain error and 3.9 widened, 1.6 and 1.3 at 400,000, 1.15 and 1.07 at
  // a million (docs/normalisation.md). No error computed from one run can cover paths it
  // never met; the remedy is more samples.
  double error() const;
  // The largest sample's share of the sum: how much one path decides.
  double largest_share() const { return sum > 0.0 ? largest / sum : 0.0; }
  // Whether the figures can be a set of non-negative samples' (a checkpoint's check).
  bool consistent() const;
};

}  // namespace emlt
