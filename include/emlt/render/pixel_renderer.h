#pragma once
// Drives integrators that estimate each pixel independently (direct, pt). Sample k of
// pixel i draws its random numbers from the stream (seed, i, k), and each pixel is summed
// by exactly one task, in sample order, so the image is bit-identical for a seed at any
// thread count and whether the samples came in one pass or many, in one run or in a run
// resumed from a checkpoint (time-limited renders use passes).
#include <functional>

#include "emlt/core/rng.h"
#include "emlt/core/state_io.h"
#include "emlt/render/integrator.h"
#include "emlt/render/pass_schedule.h"

namespace emlt {

// Radiance arriving along a camera ray; may use `rng` freely.
using RadianceEstimator = std::function<Rgb(const Ray& ray, Rng& rng)>;

// Everything a pass-based render has done: per pixel the sum of its samples and how many
// there were (all equal between passes; a stop inside a pass leaves some pixels a few
// samples ahead, and the image divides each by its own count), and the schedule.
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
  };
  Totals totals() const;
  // Whether some pixel of this rank's rows has fewer than `samples` samples (a pass cut short).
  bool behind(int samples, int width) const;
};

// Under MPI each rank renders the rows of every R-th band of 16 rows (R ranks), whole
// pixels, so every pixel's sum is made by one rank in sample order as without MPI.
bool owns_row(int y);

// The whole render of one integrator: resumes from and checkpoints through
// settings.control.
RenderResult render_pixels(const Scene& scene, const RenderSettings& settings,
                           ProgressReporter& progress, const RadianceEstimator& radiance);

// A pass-based render inside another (MLT's direct-light image): continues from `state`
// when state.resumed, leaves its final state there, and at a pause (a checkpoint or a stop,
// agreed by every rank) calls `on_pause`, which saves whatever the outer render needs. The
// image of the result is complete on rank 0 only.
RenderResult render_pixels(const Scene& scene, const RenderSettings& settings,
                           ProgressReporter& progress, const RadianceEstimator& radiance,
                           PixelRenderState& state, const std::function<void()>& on_pause);

}  // namespace emlt
