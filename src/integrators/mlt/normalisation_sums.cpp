#include "emlt/integrators/mlt/normalisation_sums.h"

#include <algorithm>
#include <cmath>

namespace emlt {

double NormalisationSums::standard_error() const {
  if (samples == 0) return 0.0;
  const double n = double(samples), mean = sum / n;
  return std::sqrt(std::max(sum_squares / n - mean * mean, 0.0) / n);
}

double NormalisationSums::error() const {
  if (samples == 0) return 0.0;
  const double plain = standard_error(), one_more = largest / double(samples);
  return std::sqrt(plain * plain + one_more * one_more);
}

bool NormalisationSums::consistent() const {
  return std::isfinite(sum) && sum >= 0.0 && std::isfinite(sum_squares) && sum_squares >= 0.0 &&
         std::isfinite(largest) && largest >= 0.0 && largest <= sum && (samples > 0 || sum == 0.0);
}

}  // namespace emlt
