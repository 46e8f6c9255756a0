#pragma once
// Integrators that estimate each pixel independently from camera rays (direct, pt), on the
// pass runner (run/pass_runner.h): sample k of pixel i draws its random numbers from the
// stream (seed, i, k), so the image is bit-identical for a seed at any thread count, in one
// pass or many, in one run or resumed from a checkpoint.
#include <functional>

#include "emlt/core/rng.h"
#include "emlt/run/integrator.h"
#include "emlt/run/pixel_state.h"

namespace emlt {

// Radiance arriving along a camera ray; may use `rng` freely.
using RadianceEstimator = std::function<Rgb(const Ray& ray, Rng& rng)>;
// The same, told the pixel (x, y) the ray samples (per-pixel state such as a prepared
// MIS split).
using PixelRadianceEstimator = std::function<Rgb(int x, int y, const Ray& ray, Rng& rng)>;

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

// render_pixels with the pixel-aware estimator.
RenderResult render_pixels_at(const Scene& scene, const RenderSettings& settings,
                              ProgressReporter& progress, const PixelRadianceEstimator& radiance);
RenderResult render_pixels_at(const Scene& scene, const RenderSettings& settings,
                              ProgressReporter& progress, const PixelRadianceEstimator& radiance,
                              PixelRenderState& state, const std::function<void()>& on_pause);

// The camera ray of sample `rng` in pixel (x, y), as render_pixels traces it (the filter's
// jitter, then the lens), and the filter's weight for it.
Ray pixel_camera_ray(const Camera& camera, int x, int y, Rng& rng, float* filter_weight = nullptr);

}  // namespace emlt
