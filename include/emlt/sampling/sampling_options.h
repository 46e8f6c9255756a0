#pragma once
// The options of path sampling shared by every integrator: path length, Russian roulette,
// whether lights seen directly count (a scene file may set these three: scene_options.h),
// MIS and the direct-light estimate (render_option.h).
#include <vector>

#include "emlt/settings/render_option.h"

namespace emlt {

const std::vector<RenderOption>& sampling_options();
// --direct-sampler bmc's hyperparameters (bmc_options.cpp), recorded only where it is chosen.
std::vector<RenderOption> bmc_options();

}  // namespace emlt
