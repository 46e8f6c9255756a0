#pragma once
// A weighted sum of BSDFs, sum_i w_i(uv) f_i (internal to the engine): what Mitsuba's
// `mixturebsdf` (constant weights) and `blendbsdf` (a texture blending two) both evaluate.
// Sampling picks one part with probability w_i / sum w, samples it, and then weighs the
// direction by the whole sum's value and density, so the density is the mixture's
// whichever part drew it.
#include <string>
#include <vector>

#include "emlt/scene/bsdf.h"
#include "emlt/scene/texture.h"

namespace emlt {

// `weights` constant, one per part, not negative, with a positive sum.
BsdfPtr make_weighted_sum(std::vector<BsdfPtr> parts, std::vector<float> weights, std::string name);
// Two parts, (1 - w) f_first + w f_second, w the channel mean of `weight` at the point
// clamped to [0, 1].
BsdfPtr make_blended_pair(TexturePtr weight, BsdfPtr first, BsdfPtr second, std::string name);

}  // namespace emlt
