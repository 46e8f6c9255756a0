#pragma once
// What a pass-based render (pass_runner.h) has done per pixel, and how the pixels are shared
// between MPI ranks: every pixel is some one rank's, whole, so its sum is made by one rank
// in sample order as without MPI, and summing the ranks' states is exact.
#include <cstdint>
#include <vector>

#include "emlt/core/math.h"
#include "emlt/core/state_io.h"
#include "emlt/image/image.h"
#include "emlt/run/pass_schedule.h"

namespace emlt {

// Per pixel the sum of its samples and how many there were (all equal between passes; a
// stop inside a pass leaves some pixels a few samples ahead, and the image divides each by
// its own count), and the schedule.
struct PixelRenderState {
  std::vector<DVec3> sums;
  std::vector<int32_t> counts;
  PassSchedule::Saved schedule;
  bool resumed = false;  // loaded from a checkpoint: the render continues from it
  uint64_t invalid = 0;

  void save(StateWriter& out) const;
  // Throws StateError when the state does not fit an image of this size.
  void load(StateReader& in, int width, int height);

  // Every rank's pixels summed on rank 0 (cluster.h); the state itself is left as it is.
  struct Totals {
    std::vector<double> sums;  // 3 per pixel
    std::vector<int32_t> counts;
    // The mean of each pixel's samples.
    Image image(int width, int height) const;
    uint64_t samples() const;  // of every pixel together
  };
  Totals totals() const;
  // Whether some pixel of this rank's rows has fewer than `samples` samples (a pass cut short).
  bool behind(int samples, int width) const;
};

// Under MPI each rank renders the rows of every R-th band of 16 rows (R ranks), whole
// pixels.
bool owns_row(int y);

}  // namespace emlt
