#pragma once
// All emitters of a scene, chosen in proportion to their power. Every integrator picks
// lights through this class so the selection probability in its pdfs is the same.
#include <vector>

#include "emlt/core/distribution.h"
#include "emlt/scene/environment.h"
#include "emlt/scene/light.h"

namespace emlt {

class LightSet {
 public:
  LightSet() = default;
  // Takes ownership; the environment (if any) may be part of `lights`.
  explicit LightSet(std::vector<LightPtr> lights);

  size_t size() const { return lights_.size(); }
  bool empty() const { return lights_.empty(); }
  const Light& light(size_t i) const { return *lights_[i]; }
  const EnvironmentLight* environment() const { return environment_; }

  // Picks a light; `probability` receives its selection probability.
  const Light* choose(float u, float* probability) const;
  float selection_probability(const Light& light) const;

 private:
  std::vector<LightPtr> lights_;
  Distribution1D power_distribution_;
  const EnvironmentLight* environment_ = nullptr;
};

}  // namespace emlt
