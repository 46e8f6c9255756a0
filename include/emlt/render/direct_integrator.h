#pragma once
#include "emlt/core/rng.h"
#include "emlt/render/integrator.h"

namespace emlt {

class DirectIntegrator final : public Integrator {
 public:
  std::string name() const override { return "direct"; }
  RenderResult render(const Scene& scene, const RenderSettings& settings,
                      ProgressReporter& progress) const override;
  // Radiance along one camera ray (exposed for tests).
  static Rgb radiance(const Scene& scene, const RenderSettings& settings, const Ray& ray, Rng& rng);
};

}  // namespace emlt
