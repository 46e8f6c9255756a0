#pragma once
#include "emlt/core/rng.h"
#include "emlt/core/sample_source.h"
#include "emlt/run/integrator.h"

namespace emlt {

// Unidirectional path tracer with next-event estimation, MIS against BSDF sampling and
// Russian roulette. The reference every other integrator is checked against.
class PathTracer final : public Integrator {
 public:
  std::string name() const override { return "pt"; }
  RenderResult render(const Scene& scene, const RenderSettings& settings,
                      ProgressReporter& progress) const override;
  static Rgb radiance(const Scene& scene, const RenderSettings& settings, const Ray& ray, Rng& rng);
  // The same estimate from a primary-sample vector (PSSMLT), counting only paths of at
  // least `min_segments` segments; `longest` (if given): the segments of the longest path
  // that added light, 0 if none did.
  static Rgb radiance(const Scene& scene, const RenderSettings& settings, const Ray& ray,
                      SampleSource& samples, int min_segments, int* longest = nullptr);
};

}  // namespace emlt
