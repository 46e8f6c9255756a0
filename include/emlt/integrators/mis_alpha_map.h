#pragma once
// Lu's "preprocessed" split (thesis 004, section 5.4.1 and Table 5.1): before the render, a
// pilot of half light, half BSDF directions at each pixel's first hits estimates the
// second-order alpha (sampling/second_order_alpha.h) from all of the pixel's pilot
// directions together; the render then draws every direction of the pixel from the mixture
// at that fixed alpha. The thesis's preprocessed alpha used M = 4096 directions per light
// and camera ray, kept apart from the render's samples; here --mis-alpha-samples directions
// per pixel, spread over camera rays of 2 * --direct-samples directions each.
//
// The pre-pass draws from its own streams (seed, pixel, ray), so the map and the render after
// it are the same bits at any thread count.
#include <vector>

#include "emlt/scene/scene.h"
#include "emlt/settings/settings.h"

namespace emlt {

// alpha per pixel, row-major over the camera's image, each within the clamp of `settings`.
std::vector<float> preprocess_mis_alpha(const Scene& scene, const RenderSettings& settings);

}  // namespace emlt
