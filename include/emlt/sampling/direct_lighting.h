#pragma once
// The shared direct-lighting estimator: light sampling (lights chosen in proportion to
// power, area lights sampled uniformly by area, the environment by its importance table)
// and BSDF sampling, combined with MIS. The `direct` integrator uses all of it; the path
// tracer uses the light-sampling half at every vertex and the emission weight for the
// BSDF-sampled continuation, so both integrators weight light exactly the same way.
#include "emlt/core/rng.h"
#include "emlt/sampling/bmc_direct_estimator.h"
#include "emlt/sampling/cube_balanced_sampler.h"
#include "emlt/scene/scene.h"
#include "emlt/settings/settings.h"

namespace emlt {

struct DirectLightingOptions {
  int samples = 1;  // light samples and BSDF samples each
  MisHeuristic heuristic = MisHeuristic::Power;
  DirectPointSet point_set = DirectPointSet::Independent;
  BmcHyperparameters bmc;                        // DirectPointSet::Bmc
  EnvSampler env_sampler = EnvSampler::LatLong;  // how the environment is sampled
  CubeFaceBalance env_face_balance = CubeFaceBalance::Receiver;
  int env_cube_resolution = 0;
  EnvFaceCounts env_face_counts = EnvFaceCounts::Sampled;  // the light half under cube-balanced
  // MisHeuristic::SecondOrder (mixture_direct_estimator.h): the 2 * samples directions come
  // from the light/BSDF mixture, its light share fixed by `alpha` in [0, 1] or, when alpha
  // is negative, chosen online by Lu's second-order rule (its pilot share and clamp here).
  // The point set is then independent.
  double alpha = -1.0;
  double alpha_pilot = 0.5;
  double alpha_clamp = 0.025;
  // DirectPointSet::Adaptive (adaptive_direct_sampler.h): 2 * samples directions.
  int adaptive_initial = 1;
  double adaptive_robustness = 1.0;
  AdaptiveParametrisation adaptive_parametrisation = AdaptiveParametrisation::Cosine;
};

// One randomised set of n unit-square points of kind `set` (each point marginally uniform,
// so an estimate built on it stays unbiased); empty for independent points (and for the
// estimators that are not point sets), which are drawn one at a time.
std::vector<Vec2> draw_direct_point_set(DirectPointSet set, uint32_t n, Rng& rng);

// One light-sampling estimate of the radiance reflected at `hit` towards wo (world, unit),
// MIS-weighted against BSDF sampling. `u_select` picks the light, `u_light` the point;
// `env` says how the environment is sampled at this point (default: its own table).
Rgb sample_light_contribution(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                              TransportMode mode, float u_select, const Vec2& u_light,
                              MisHeuristic heuristic, const EnvironmentSampling& env = {});

// The same estimate for a light sample already drawn: `ls` from `light`, chosen with
// probability `selection` (ls->pdf is the density the sample was drawn with given the light).
Rgb drawn_light_contribution(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                             TransportMode mode, const Light& light, float selection,
                             const std::optional<DirectLightSample>& ls, MisHeuristic heuristic);

// Emission found by a BSDF-sampled ray: radiance arriving at `from` along `direction`
// from the emitter at `emitter_hit` (or from the environment when `emitter_hit` is null),
// MIS-weighted against light sampling. `bsdf_pdf` is the solid-angle density the BSDF
// sample was drawn with; `delta` marks a specular sample, which light sampling cannot make.
// `env`: how light sampling at `from` samples the environment.
Rgb weighted_emission(const Scene& scene, const Vec3& from, const Vec3& direction,
                      const SurfaceHit* emitter_hit, float bsdf_pdf, bool delta,
                      MisHeuristic heuristic, const EnvironmentSampling& env = {});

// Full direct-lighting estimate at a camera-visible point: `options.samples` light samples
// and as many BSDF samples, each set either independent or a randomised spherical
// Fibonacci set (unbiased; see spherical_fibonacci.h) or, likewise, from a randomised
// Sobol, Larcher-Pillichshammer or blue-noise set (core/sobol_points.h,
// core/larcher_pillichshammer_points.h, core/blue_noise_points.h); under SecondOrder, as many
// directions in all from the mixture of the two. DirectPointSet::Bmc: 2 * samples directions
// by Bayesian Monte Carlo (biased) where the BSDF allows it (bmc_direct_estimator.h), the
// independent MIS estimate elsewhere. DirectPointSet::Adaptive: Szécsi et al.'s adaptive
// quadrature over 2 * samples directions (biased), except at a BSDF with a delta lobe, which
// only BSDF sampling finds.
Rgb estimate_direct_lighting(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, Rng& rng,
                             const DirectLightingOptions& options);

}  // namespace emlt
