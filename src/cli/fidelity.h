#pragma once
// How faithfully a scene file will be rendered: every item the loader approximates or
// cannot honour (SceneDescription::divergences), said before a long render starts.
#include "emlt/scene/description.h"

namespace emlt::cli {

// Under --strict, any divergence is an error naming the first one and the count.
void refuse_divergences_if_strict(const SceneDescription& desc, bool strict);

// One warning line summing the divergences ("" for a scene rendered exactly).
std::string divergence_summary(const SceneDescription& desc);

}  // namespace emlt::cli
