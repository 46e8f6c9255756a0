// Mitsuba 0.6's `mixturebsdf`: a constant-weighted sum of BSDFs. Its weights are used as
// given unless they sum to more than 1 and energy conservation is asked for (Mitsuba's
// default), when they are divided by their sum.
#include <stdexcept>
#include <utility>

#include "emlt/scene/materials.h"
#include "src/scene/materials/weighted_sum.h"

namespace emlt {

BsdfPtr make_mixture(std::vector<BsdfPtr> parts, std::vector<float> weights,
                     bool ensure_energy_conservation) {
  if (parts.empty() || parts.size() != weights.size())
    throw std::invalid_argument("a mixture needs one weight per BSDF");
  float total = 0.0f;
  for (float w : weights) {
    if (!(w >= 0.0f)) throw std::invalid_argument("a mixture's weights must not be negative");
    total += w;
  }
  if (!(total > 0.0f)) throw std::invalid_argument("a mixture's weights must sum to more than 0");
  if (ensure_energy_conservation && total > 1.0f)
    for (float& w : weights) w /= total;
  return make_weighted_sum(std::move(parts), std::move(weights), "mixture");
}

}  // namespace emlt
