#pragma once
// The options of the path-space MLT family (render_option.h), in three groups: what every
// chain driver of the family reads (budget in mutations, chains, bootstrap, mix, direct
// pass, statistics), the geometry-aware perturbations' (gamlt), and the ensemble's (emlt).
#include <vector>

#include "emlt/settings/render_option.h"

namespace emlt {

const std::vector<RenderOption>& mlt_options();
const std::vector<RenderOption>& gamlt_options();
const std::vector<RenderOption>& ensemble_options();

}  // namespace emlt
