// `direct`: emission seen by the camera plus one bounce of MIS direct lighting (light and
// BSDF sampling). This is the EMLT paper's direct-lighting baseline.
#include "emlt/render/direct_integrator.h"

#include "emlt/render/direct_lighting.h"
#include "emlt/render/pixel_renderer.h"

namespace emlt {

Rgb DirectIntegrator::radiance(const Scene& scene, const RenderSettings& settings, const Ray& ray,
                               Rng& rng) {
  SurfaceHit hit;
  if (!scene.intersect(ray, hit)) {
    const EnvironmentLight* env = scene.environment();
    return env ? env->radiance(ray.direction) : Rgb(0.0f);
  }
  const Vec3 wo = -ray.direction;
  Rgb result = hit.emitted(wo);
  if (settings.max_depth >= 0 && settings.max_depth < 2) return result;
  DirectLightingOptions options;
  options.samples = settings.direct_samples;
  options.heuristic = settings.mis;
  options.point_set = settings.direct_point_set;
  return result + estimate_direct_lighting(scene, hit, wo, rng, options);
}

RenderResult DirectIntegrator::render(const Scene& scene, const RenderSettings& settings,
                                      ProgressReporter& progress) const {
  return render_pixels(scene, settings, progress,
                       [&](const Ray& ray, Rng& rng) { return radiance(scene, settings, ray, rng); });
}

}  // namespace emlt
