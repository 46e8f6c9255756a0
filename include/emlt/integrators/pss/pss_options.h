#pragma once
// The options of primary-sample-space MLT (pssmlt, mmlt; render_option.h). Its budget,
// chains, bootstrap and direct pass are the MLT family's (mlt_options.h).
#include <vector>

#include "emlt/settings/render_option.h"

namespace emlt {

const std::vector<RenderOption>& pss_options();

}  // namespace emlt
