#include "emlt/integrators/path_tracer.h"

#include "emlt/integrators/path_tracer_estimate.h"
#include "emlt/integrators/pixel_renderer.h"

namespace emlt {

Rgb PathTracer::radiance(const Scene& scene, const RenderSettings& settings, const Ray& ray,
                         Rng& rng) {
  return path_tracer_estimate(scene, settings, ray, rng, settings.shortest_path(), nullptr);
}

Rgb PathTracer::radiance(const Scene& scene, const RenderSettings& settings, const Ray& ray,
                         SampleSource& samples, int min_segments, int* longest) {
  return path_tracer_estimate(scene, settings, ray, samples, min_segments, longest);
}

RenderResult PathTracer::render(const Scene& scene, const RenderSettings& settings,
                                ProgressReporter& progress) const {
  return render_pixels(scene, settings, progress, [&](const Ray& ray, Rng& rng) {
    return radiance(scene, settings, ray, rng);
  });
}

}  // namespace emlt
