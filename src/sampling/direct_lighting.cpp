#include "emlt/sampling/direct_lighting.h"

#include "emlt/core/blue_noise_points.h"
#include "emlt/core/larcher_pillichshammer_points.h"
#include "emlt/core/sobol_points.h"
#include "emlt/core/spherical_fibonacci.h"
#include "emlt/sampling/adaptive_direct_sampler.h"
#include "emlt/sampling/direct_sample.h"
#include "emlt/sampling/fractional_light_counts.h"
#include "emlt/sampling/mixture_direct_estimator.h"
#include "emlt/sampling/mis.h"

namespace emlt {

namespace {

// Under strict normals, light from the lower geometric hemisphere must not reach the upper
// one through an interpolated shading normal, and vice versa.
bool consistent_sides(const Scene& scene, const SurfaceHit& hit, const Vec3& w_world,
                      const Vec3& w_local) {
  return scene.sides_agree(hit.geometric_normal, w_world, w_local.z);
}

}  // namespace

// One randomised set of n unit-square points (each point marginally uniform, so the
// estimate stays unbiased); empty for independent points, which are drawn one at a time.
std::vector<Vec2> draw_direct_point_set(DirectPointSet set, uint32_t n, Rng& rng) {
  switch (set) {
    case DirectPointSet::Fibonacci:
      return fibonacci_square_points(n, FibonacciRandomisation::draw(rng));
    case DirectPointSet::Sobol: return sobol_square_points(n, DigitScramble::draw(rng));
    case DirectPointSet::LarcherPillichshammer:
      return larcher_pillichshammer_square_points(n, DigitScramble::draw(rng));
    case DirectPointSet::BlueNoise: return blue_noise_square_points(n, rng.uniform2());
    default: return {};
  }
}

Rgb sample_light_contribution(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                              TransportMode mode, float u_select, const Vec2& u_light,
                              MisHeuristic heuristic, const EnvironmentSampling& env) {
  const LightSet& lights = scene.lights();
  if (lights.empty() || hit.bsdf->is_purely_delta()) return Rgb(0.0f);
  float selection = 0.0f;
  const Light* light = lights.choose(u_select, &selection);
  if (!light || selection <= 0.0f) return Rgb(0.0f);
  const auto ls = env.cube && light == scene.environment()
                      ? sample_environment_direct(*scene.environment(), env, hit.position, u_light)
                      : light->sample_direct(hit.position, u_light);
  return drawn_light_contribution(scene, hit, wo, mode, *light, selection, ls, heuristic);
}

Rgb drawn_light_contribution(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                             TransportMode mode, const Light& light, float selection,
                             const std::optional<DirectLightSample>& ls, MisHeuristic heuristic) {
  if (!ls || ls->pdf <= 0.0f || is_black(ls->radiance)) return Rgb(0.0f);

  const Vec3 wo_local = hit.shading.to_local(wo), wi_local = hit.shading.to_local(ls->wi);
  if (!consistent_sides(scene, hit, ls->wi, wi_local) ||
      !consistent_sides(scene, hit, wo, wo_local))
    return Rgb(0.0f);
  const BsdfContext ctx{hit.uv, mode, hit.vertex_color};
  const Rgb f = hit.bsdf->eval(ctx, wo_local, wi_local);
  if (is_black(f)) return Rgb(0.0f);

  const bool unoccluded =
      light.at_infinity()
          ? !scene.occluded(spawn_ray(hit.position, hit.geometric_normal, ls->wi))
          : scene.visible(hit.position, hit.geometric_normal, ls->position, ls->normal);
  if (!unoccluded) return Rgb(0.0f);

  const float light_pdf = selection * ls->pdf;
  // BSDF sampling never finds a delta light: its light sample has the whole weight.
  const float weight =
      ls->delta ? 1.0f : mis_weight(heuristic, light_pdf, hit.bsdf->pdf(ctx, wo_local, wi_local));
  return f * std::abs(wi_local.z) * ls->radiance * (weight / light_pdf);
}

Rgb weighted_emission(const Scene& scene, const Vec3& from, const Vec3& direction,
                      const SurfaceHit* emitter_hit, float bsdf_pdf, bool delta,
                      MisHeuristic heuristic, const EnvironmentSampling& env) {
  const ArrivingEmission e = arriving_emission(scene, from, direction, emitter_hit, !delta, env);
  if (delta || is_black(e.radiance)) return e.radiance;
  return e.radiance * mis_weight(heuristic, bsdf_pdf, e.light_pdf);
}

Rgb estimate_direct_lighting(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, Rng& rng,
                             const DirectLightingOptions& options) {
  // Under strict normals an arrival the two normals disagree on reflects nothing (Mitsuba's
  // direct integrator skips the point); the light samples would be zero, the BSDF's not.
  if (!consistent_sides(scene, hit, wo, hit.shading.to_local(wo))) return Rgb(0.0f);
  const int n = glm::max(options.samples, 1);
  if (options.point_set == DirectPointSet::Bmc)
    if (const auto bmc = estimate_direct_bmc(scene, hit, wo, rng, 2 * n, options.bmc)) return *bmc;
  const EnvironmentSampling env = environment_sampling(
      scene, options.env_sampler, hit, wo, options.env_face_balance, options.env_cube_resolution);
  if (options.point_set == DirectPointSet::Adaptive && !hit.bsdf->has_delta_lobe()) {
    // The cosine map covers one hemisphere: a BSDF that transmits takes the whole sphere.
    const bool transmits = (hit.bsdf->lobes() & kLobeTransmission) != 0;
    return estimate_direct_adaptive(
        scene, hit, wo, rng,
        AdaptiveDirectOptions{
            2 * n, options.adaptive_initial, options.adaptive_robustness,
            transmits ? AdaptiveParametrisation::Global : options.adaptive_parametrisation});
  }
  if (options.heuristic == MisHeuristic::SecondOrder) {
    if (options.alpha >= 0.0)
      return estimate_direct_mixture(scene, hit, wo, rng, options.alpha, 2 * n, env);
    return estimate_direct_second_order(scene, hit, wo, rng, 2 * n,
                                        SecondOrderSplit{options.alpha_pilot, options.alpha_clamp},
                                        nullptr, env);
  }
  // Lu's fractional counts give each light and face its expected share of the light samples
  // (each technique its own point set).
  const bool fractional = env.cube && options.env_face_counts == EnvFaceCounts::Fractional;
  std::vector<Vec2> light_points =
      fractional ? std::vector<Vec2>{} : draw_direct_point_set(options.point_set, uint32_t(n), rng);
  std::vector<Vec2> bsdf_points = draw_direct_point_set(options.point_set, uint32_t(n), rng);
  const auto point = [&](std::vector<Vec2>& set, int i) {
    return set.empty() ? rng.uniform2() : set[size_t(i)];
  };

  Rgb total(0.0f);
  if (fractional)
    total = light_samples_by_fractional_counts(scene, hit, wo, n, options.heuristic, env,
                                               options.point_set, rng);
  const Vec3 wo_local = hit.shading.to_local(wo);
  const BsdfContext ctx{hit.uv, TransportMode::Radiance, hit.vertex_color};
  for (int i = 0; i < n; ++i) {
    if (!fractional) {
      const float u_select = rng.uniform();
      total += sample_light_contribution(scene, hit, wo, TransportMode::Radiance, u_select,
                                         point(light_points, i), options.heuristic, env);
    }

    const float u_lobe = rng.uniform();
    const auto bs = hit.bsdf->sample(ctx, wo_local, u_lobe, point(bsdf_points, i));
    if (!bs || is_black(bs->weight)) continue;
    const Vec3 wi = hit.shading.to_world(bs->wi);
    if (!consistent_sides(scene, hit, wi, bs->wi)) continue;
    SurfaceHit next;
    const bool found = scene.intersect(spawn_ray(hit.position, hit.geometric_normal, wi), next);
    total += bs->weight * weighted_emission(scene, hit.position, wi, found ? &next : nullptr,
                                            bs->pdf, bs->is_delta(), options.heuristic, env);
  }
  return total / float(n);
}

}  // namespace emlt
