#include "emlt/mcmc/alpha_tally.h"

#include <algorithm>
#include <cmath>

namespace emlt {

void AlphaTally::add(double alpha) {
  const double bin = std::floor(alpha * kBinsPerUnit);
  ++counts[size_t(std::clamp(std::isfinite(bin) ? bin : 0.0, 0.0, double(kBins - 1)))];
  sum += alpha;
  min = std::min(min, alpha);
  max = std::max(max, alpha);
}

void AlphaTally::merge(const AlphaTally& other) {
  for (size_t i = 0; i < counts.size(); ++i) counts[i] += other.counts[i];
  sum += other.sum;
  min = std::min(min, other.min);
  max = std::max(max, other.max);
}

uint64_t AlphaTally::total() const {
  uint64_t n = 0;
  for (const uint64_t c : counts) n += c;
  return n;
}

double AlphaTally::quantile(double q) const {
  const uint64_t n = total();
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  // The smallest bin whose cumulative count reaches q n (at least the first entry).
  const double wanted = std::max(1.0, std::ceil(std::clamp(q, 0.0, 1.0) * double(n)));
  uint64_t seen = 0;
  for (size_t i = 0; i < counts.size(); ++i) {
    seen += counts[i];
    if (double(seen) >= wanted) return std::clamp((double(i) + 0.5) / kBinsPerUnit, min, max);
  }
  return max;
}

double AlphaTally::mean() const {
  const uint64_t n = total();
  return n ? sum / double(n) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace emlt
