#pragma once
// The distribution of the stretch scale α that EMLT's guided linear kernels drew with (§3.4),
// one entry per guided step that made a proposal: --stats reports its minimum, quartiles,
// maximum and mean, so that a render shows whether α adapted. Counts in fixed bins (width
// 1/256 on [0, 2), the last bin open above), so tallies merge to the same bits in any order;
// quartiles are bin midpoints clamped to the exact extremes.
#include <array>
#include <cstdint>
#include <limits>

namespace emlt {

struct AlphaTally {
  static constexpr int kBins = 512;
  static constexpr double kBinsPerUnit = 256.0;

  std::array<uint64_t, kBins> counts{};
  double sum = 0.0;
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();

  void add(double alpha);
  void merge(const AlphaTally& other);
  uint64_t total() const;
  // The q-quantile (0 <= q <= 1) to a bin's width; NaN when empty.
  double quantile(double q) const;
  double mean() const;
};

}  // namespace emlt
