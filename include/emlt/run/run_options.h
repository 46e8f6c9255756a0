#pragma once
// The options of the run loop itself, whatever the integrator: the budget, the seed, the
// threads (render_option.h); a scene file may set the sample count (scene_options.h).
#include <vector>

#include "emlt/settings/render_option.h"

namespace emlt {

const std::vector<RenderOption>& run_options();

}  // namespace emlt
