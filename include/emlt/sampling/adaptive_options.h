#pragma once
// The options of `--direct-sampler adaptive` (sampling/adaptive_direct_sampler.h); they change
// a render only under that sampler, so only such renders record them.
#include <vector>

#include "emlt/settings/render_option.h"

namespace emlt {

const std::vector<RenderOption>& adaptive_sampler_options();

}  // namespace emlt
