// `direct`: emission seen by the camera plus one bounce of MIS direct lighting (light and
// BSDF sampling). This is the EMLT paper's direct-lighting baseline.
#include "emlt/integrators/direct_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "emlt/integrators/mis_alpha_map.h"
#include "emlt/integrators/pixel_renderer.h"
#include "emlt/run/progress.h"
#include "emlt/sampling/direct_lighting.h"

namespace emlt {

Rgb DirectIntegrator::radiance(const Scene& scene, const RenderSettings& settings, const Ray& ray,
                               Rng& rng, double pixel_alpha) {
  SurfaceHit hit;
  if (!scene.intersect(ray, hit)) {
    const EnvironmentLight* env = scene.environment();
    return env && !settings.hide_emitters ? env->radiance(ray.direction) : Rgb(0.0f);
  }
  const Vec3 wo = -ray.direction;
  Rgb result = settings.hide_emitters ? Rgb(0.0f) : hit.emitted(wo);
  if (settings.max_depth >= 0 && settings.max_depth < 2) return result;
  DirectLightingOptions options;
  options.samples = settings.direct_samples;
  options.heuristic = settings.mis;
  options.point_set = settings.direct_point_set;
  options.bmc = {settings.bmc_noise, settings.bmc_lengthscale_factor};
  options.env_sampler = settings.env_sampler;
  options.env_face_balance = settings.env_face_balance;
  options.env_cube_resolution = settings.env_cube_resolution;
  options.env_face_counts = settings.env_face_counts;
  options.alpha = settings.mis_alpha >= 0.0 ? settings.mis_alpha : pixel_alpha;
  options.alpha_pilot = settings.mis_alpha_pilot;
  options.alpha_clamp = settings.mis_alpha_clamp;
  options.adaptive_initial = settings.adaptive_initial;
  options.adaptive_robustness = settings.adaptive_robustness;
  options.adaptive_parametrisation = settings.adaptive_parametrisation;
  return result + estimate_direct_lighting(scene, hit, wo, rng, options);
}

RenderResult DirectIntegrator::render(const Scene& scene, const RenderSettings& settings,
                                      ProgressReporter& progress) const {
  if (settings.mis == MisHeuristic::SecondOrder && settings.mis_alpha < 0.0 &&
      settings.mis_alpha_estimate == MisAlphaEstimate::Preprocessed &&
      !(settings.max_depth >= 0 && settings.max_depth < 2)) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<float> alpha = preprocess_mis_alpha(scene, settings);
    const double pre_pass =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int width = scene.camera().width();
    RenderResult result = render_pixels_at(scene, settings, progress,
                                           [&](int x, int y, const Ray& ray, Rng& rng) {
                                             const size_t pixel =
                                                 size_t(y) * size_t(width) + size_t(x);
                                             return radiance(scene, settings, ray, rng,
                                                             double(alpha[pixel]));
                                           });
    result.seconds += pre_pass;  // the pre-pass is part of the render's cost
    return result;
  }
  return render_pixels(scene, settings, progress, [&](const Ray& ray, Rng& rng) {
    return radiance(scene, settings, ray, rng);
  });
}

RenderResult render_direct_pass(const Scene& scene, const RenderSettings& settings,
                                PixelRenderState& state, const std::function<void()>& on_pause,
                                double share) {
  RenderSettings direct = settings;
  const bool time_only = settings.time_limit_s > 0.0 && !(settings.mutations_per_pixel > 0.0);
  constexpr double kDirectTimeShare = 0.15;
  const int spp = settings.direct_spp > 0 ? settings.direct_spp
                  : time_only             ? 0
                              : std::max(1, int(std::ceil(settings.mutations_per_pixel)));
  // Up to the share of the samples, never fewer than a resumed state has done or begun
  // within the budget (beyond it, the schedule refuses the state).
  const int begun = std::max(state.schedule.done, state.schedule.pass_end);
  direct.spp = spp <= 0 ? 0
               : begun > spp
                   ? spp
                   : std::max({int(std::ceil(std::clamp(share, 0.0, 1.0) * spp)), begun, 1});
  direct.time_limit_s = time_only && settings.direct_spp <= 0
                            ? kDirectTimeShare * settings.time_limit_s * share
                            : 0.0;
  direct.snapshots = nullptr;  // the log follows the chains, not this pass
  direct.control = nullptr;    // its state is part of the outer render's
  // A pre-pass per slice would repeat itself: a preprocessed split is estimated online here.
  direct.mis_alpha_estimate = MisAlphaEstimate::Online;
  ProgressReporter quiet(false);
  return render_pixels(
      scene, direct, quiet,
      [&](const Ray& ray, Rng& rng) { return DirectIntegrator::radiance(scene, direct, ray, rng); },
      state, on_pause);
}

}  // namespace emlt
