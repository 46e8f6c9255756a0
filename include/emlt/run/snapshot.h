#pragma once
// Intermediate images for convergence logs. Integrators end their passes (or MLT rounds)
// at power-of-two samples (mutations) per pixel whether or not anyone listens, so taking
// snapshots never changes the schedule, the chains or the final image.
#include <cstdint>
#include <string>
#include <vector>

#include "emlt/image/image.h"

namespace emlt {

struct StrategyAcceptance {
  std::string name;
  double mean_acceptance = 0.0;
};

class SnapshotSink {
 public:
  virtual ~SnapshotSink() = default;
  // per_pixel: samples or mutations per pixel so far; seconds: rendering time so far,
  // without the time spent in earlier snapshots.
  virtual void snapshot(double per_pixel, double seconds, const Image& image,
                        const std::vector<StrategyAcceptance>& strategies) = 0;
};

// The first checkpoint (power of two) above `done`.
inline uint64_t next_checkpoint(uint64_t done) {
  uint64_t p = 1;
  while (p <= done) p <<= 1;
  return p;
}
inline bool is_checkpoint(uint64_t n) {
  return n != 0 && (n & (n - 1)) == 0;
}

}  // namespace emlt
