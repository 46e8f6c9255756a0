// Mitsuba 0.6's `blendbsdf`: two BSDFs blended by a weight that may vary over the surface
// (a texture's channel mean, clamped to [0, 1]); 0 is the first BSDF alone, 1 the second.
// The weights always sum to 1, so there is nothing to conserve.
#include <utility>

#include "emlt/scene/materials.h"
#include "src/scene/materials/weighted_sum.h"

namespace emlt {

BsdfPtr make_blend(TexturePtr weight, BsdfPtr first, BsdfPtr second) {
  return make_blended_pair(std::move(weight), std::move(first), std::move(second), "blend");
}

BsdfPtr make_blend(float weight, BsdfPtr first, BsdfPtr second) {
  return make_blend(make_constant_texture(Rgb(weight)), std::move(first), std::move(second));
}

}  // namespace emlt
