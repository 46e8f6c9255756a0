#pragma once
// Drives integrators that estimate each pixel independently (direct, pt). Sample k of
// pixel i draws its random numbers from the stream (seed, i, k), and each pixel is summed
// by exactly one task, so the image is bit-identical for a seed at any thread count and
// whether the samples came in one pass or many (time-limited renders use passes).
#include <functional>

#include "emlt/core/rng.h"
#include "emlt/render/integrator.h"

namespace emlt {

// Radiance arriving along a camera ray; may use `rng` freely.
using RadianceEstimator = std::function<Rgb(const Ray& ray, Rng& rng)>;

RenderResult render_pixels(const Scene& scene, const RenderSettings& settings,
                           ProgressReporter& progress, const RadianceEstimator& radiance);

}  // namespace emlt
