#include "emlt/scene/light_set.h"

namespace emlt {

LightSet::LightSet(std::vector<LightPtr> lights) : lights_(std::move(lights)) {
  std::vector<float> weights;
  weights.reserve(lights_.size());
  for (size_t i = 0; i < lights_.size(); ++i) {
    Light& light = *lights_[i];
    light.index = int(i);
    if (light.is_environment() && !environment_) {
      environment_ = static_cast<const EnvironmentLight*>(&light);
    }
    // Selection by luminous power. Note that an environment's power depends on the scene
    // bounds, so the scene must call set_scene_bounds() before building the set.
    const float weight = luminance(light.power());
    weights.push_back(std::isfinite(weight) && weight > 0.0f ? weight : 0.0f);
  }
  power_distribution_ = Distribution1D(std::move(weights));
}

const Light* LightSet::choose(float u, float* probability) const {
  // With no emitted power at all, no light can contribute: report "nothing chosen"
  // instead of falling back to a uniform pick whose samples would all be black.
  if (lights_.empty() || power_distribution_.empty_mass()) {
    if (probability) *probability = 0.0f;
    return nullptr;
  }
  float pmf = 0.0f;
  const size_t i = power_distribution_.sample_discrete(u, &pmf);
  if (probability) *probability = pmf;
  return lights_[i].get();
}

float LightSet::selection_probability(const Light& light) const {
  if (power_distribution_.empty_mass() || light.index < 0) return 0.0f;
  const auto i = size_t(light.index);
  // A light from another set could carry a valid-looking index: check identity.
  if (i >= lights_.size() || lights_[i].get() != &light) return 0.0f;
  return power_distribution_.pmf(i);
}

}  // namespace emlt
