#pragma once
// Every knob of a render, read-only once the render starts. The options that set them are
// declared by the parts that read them (render_option.h: the flag, its values, its checkpoint
// record, its Mitsuba parameter), and the command line and checkpoints derive from those.
#include <cstdint>
#include <optional>
#include <string>

namespace emlt {

class SnapshotSink;
class RenderControl;

// Limits the command line and the scene files share. Beyond them a render could not
// finish in any useful time, or its counters (samples x pixels in 64 bits) and buffers
// (bootstrap candidates) would overflow memory, so they are refused before it starts.
inline constexpr int kMaxSpp = 1 << 24;  // samples (and mutations) per pixel
inline constexpr int kMaxBootstrapSamples = 1 << 24;
inline constexpr int kMaxThreads = 1024;                   // 0 means every core TBB may use
inline constexpr double kMaxTimeSeconds = 30.0 * 86400.0;  // --time: 30 days

// SecondOrder: the direct-lighting estimate samples the one-sample mixture of light and
// BSDF sampling with Lu's second-order split (sampling/second_order_alpha.h); wherever a
// weight between more strategies or a fixed pair of samples is needed (path tracer, BDPT)
// it weights as Balance, which is the mixture at alpha = 1/2 (thesis Eq. 5.3).
enum class MisHeuristic { Balance, Power, Max, SecondOrder };
// How --mis second-order finds its split when --mis-alpha does not fix it.
enum class MisAlphaEstimate { Online, Preprocessed };
// Bmc: not a point set but Bayesian Monte Carlo's own estimator (sampling/bmc_direct_estimator.h);
// Adaptive: Szécsi et al.'s deterministic Halton-cell quadrature
// (sampling/adaptive_direct_sampler.h). Both are biased; only `direct` accepts them.
// Sobol, LarcherPillichshammer, BlueNoise: randomised unit-square point sets like Fibonacci
// (core/sobol_points.h, core/larcher_pillichshammer_points.h, core/blue_noise_points.h),
// unbiased, accepted wherever Fibonacci is.
enum class DirectPointSet {
  Independent,
  Fibonacci,
  Bmc,
  Adaptive,
  Sobol,
  LarcherPillichshammer,
  BlueNoise
};
// The unit square's map onto directions under --direct-sampler adaptive: the diffuse BRDF's
// (the hemisphere, seed 001 section 4.2) or the global spherical one (section 4.1).
enum class AdaptiveParametrisation { Cosine, Global };
// How direct lighting samples an environment: its lat-long texel table, or Lu's cube faces
// balanced per shading point (sampling/cube_balanced_sampler.h).
enum class EnvSampler { LatLong, CubeBalanced };
// How cube-balanced shares the samples among the faces: Lu's per-receiver weights (Eq. 3.4),
// equally among the faces with light (the thesis's Fig. 3.6 comparison), or by each face's
// mass alone (a global luminance CDF over the cube).
enum class CubeFaceBalance { Receiver, Uniform, Mass };
// How `direct` shares its light samples among the faces (and lights) under cube-balanced:
// each sample chooses one at random, or each gets its expected count outright, the last
// sample weighted by the fraction (Lu's Eqs. 3.5-3.6, sampling/fractional_light_counts.h).
enum class EnvFaceCounts { Sampled, Fractional };

struct RenderSettings {
  std::string integrator = "pt";
  int spp = 16;
  double time_limit_s = 0.0;  // > 0: render passes until the time is up (spp is then a cap)
  uint64_t seed = 1;
  int threads = 0;            // 0: all hardware threads
  int width = 0, height = 0;  // 0: from the scene
  int max_depth = -1;         // longest path in segments; -1 = unlimited (Russian roulette ends it)
  int rr_depth = 5;           // Russian roulette starts after this many segments (a bidirectional
                              // subpath: at this segment, as Mitsuba's; see subpath_rr_depth)
  // Mitsuba's hideEmitters: light that reaches the camera without scattering (paths of one
  // segment: an emitter or the sky seen directly) is left out, by every integrator.
  bool hide_emitters = false;
  int shortest_path() const { return hide_emitters ? 2 : 1; }  // in segments
  MisHeuristic mis = MisHeuristic::Power;
  // --mis second-order (sampling/mixture_direct_estimator.h). mis_alpha in [0, 1]: the fixed
  // fraction of direct-lighting directions drawn by light sampling; < 0: estimated per
  // shading point (Online, Lu's Eq. 5.6) or per pixel in a pre-pass (Preprocessed).
  double mis_alpha = -1.0;
  MisAlphaEstimate mis_alpha_estimate = MisAlphaEstimate::Online;
  // Online: the share of a shading point's directions spent on the half/half pilot that
  // estimates alpha (Lu's Table 5.2: M = N, a half).
  double mis_alpha_pilot = 0.5;
  // Preprocessed: pilot directions per pixel in the pre-pass (Lu's Table 5.1 used 4096 per
  // light and camera ray; 256 keeps the pre-pass below the render's own cost at 256
  // directions per pixel, docs/direct-samplers.md).
  int mis_alpha_samples = 256;
  // The estimate is clamped to [c, 1 - c] (Lu's Fig. 5.4 and section 5.4.3: 0.025).
  double mis_alpha_clamp = 0.025;
  int direct_samples = 1;  // light and BSDF samples per direct-lighting estimate
  DirectPointSet direct_point_set = DirectPointSet::Independent;
  // --direct-sampler bmc: the GP's noise ratio and lengthscale factor (l = factor / sqrt(m)),
  // by default the fast rule of Marques et al. (TVCG 2013, section 5.4).
  double bmc_noise = 0.5;
  double bmc_lengthscale_factor = 1.25;
  // --direct-sampler adaptive: points placed uniformly before the errors decide (1: the
  // paper's single root cell), the robustness term's factor, and the parametrisation.
  int adaptive_initial = 1;
  double adaptive_robustness = 1.0;
  AdaptiveParametrisation adaptive_parametrisation = AdaptiveParametrisation::Cosine;
  // How direct lighting samples the environment (direct, pt, --direct separate).
  EnvSampler env_sampler = EnvSampler::LatLong;
  CubeFaceBalance env_face_balance = CubeFaceBalance::Receiver;
  int env_cube_resolution = 0;  // cube-balanced: texels per face edge; 0: from the map
  // Only `direct` draws several light samples per point; the path tracer and the chains'
  // direct pass draw one, so there the face is always chosen per sample.
  EnvFaceCounts env_face_counts = EnvFaceCounts::Fractional;
  bool progress = true;

  // Metropolis light transport (integrator "mlt").
  double mutations_per_pixel = 16.0;  // --mpp: total mutations = mpp * width * height
  int chains = 0;                     // 0: chosen from the budget (reported)
  int bootstrap_samples = 100000;     // BDPT samples for b and the chains' seeds
  // Unless --bootstrap is given, the mlt family's pool then grows while it is worth fewer
  // than two candidates a chain, within a share of the budget (bootstrap.h).
  bool bootstrap_grows = true;
  // --bootstrap-seed: the stream of the bootstrap and of the chains' start paths, when it
  // should stay fixed while --seed varies the chains (as Mitsuba's MLT, whose luminance pass
  // and seed paths come from one fixed stream): the variance across --seed is then the
  // chains' alone. Unset: --seed.
  std::optional<uint64_t> bootstrap_seed;
  uint64_t start_seed() const { return bootstrap_seed.value_or(seed); }
  // --normalisation-rate: bootstrap samples drawn per chain mutation beside the chains of
  // mlt, gamlt and emlt, so that b keeps converging (normalisation_pass.h); 0: the
  // bootstrap's b alone. 1/64 costs about a tenth of the render (a sample took 4.2 to 7.2
  // mutations' time on the Cornell box, the caustic pool and the door).
  double normalisation_rate = 1.0 / 64.0;
  // ERPT (erpt_integrator.h): chains started per pixel on average over the --spp seeds
  // (Mitsuba's numChains), at most this many per seed path (0: no bound), steps per chain.
  double erpt_chains = 1.0;
  double erpt_max_chains = 0.0;
  int erpt_chain_length = 100;
  // --mutations name=weight,...; empty: the integrator's own default mix (mlt_integrator.h).
  std::string mutations;
  bool direct_separate = true;  // --direct separate|mlt
  // Samples of the separate direct image; 0: as many as mutations per pixel (at least 1),
  // so the direct part converges with the chains, or 15 % of a pure time budget.
  int direct_spp = 0;
  std::string stats_path;  // --stats FILE.json
  // Writes the predominant image-plane direction of the chains' proposals per pixel (the
  // EMLT paper's Figure 12) to this PNG; empty: not recorded.
  std::string aniso_map_path;

  // Primary-sample-space MLT (integrators "pssmlt" and "mmlt"; integrators/pss/pss_integrator.h).
  bool pss_bdpt = false;                // --pss-tracer bdpt (pssmlt); false: the path tracer
  double large_step_probability = 0.3;  // --large-step
  double pss_sigma = 1.0 / 64.0;        // --pss-sigma: the largest small-step perturbation

  // Path-space MLT (mlt, gamlt, emlt): each step scores the proposal with its acceptance
  // probability and the current path with the rest (expected values); false: the state
  // after the step alone, as the original MLT papers' chains (--mlt-splat state).
  bool mlt_expected_values = true;

  // Ensemble MLT (integrator "emlt"; include/emlt/mcmc/ensemble_guides.h).
  int ensemble_size = 0;        // |X| = |Y|; 0: 16384, fewer on images under 32768 pixels
  int ensemble_neighbours = 0;  // M, the guide paths of one step; 0: EnsembleParams' (8)
  int ensemble_iterations = 0;  // steps per path between swaps; 0: floor(W H / (|X| + |Y|))
  double ensemble_alpha = 0.0;  // > 0: fixed α of the linear kernels; 0: adaptive (paper §3.4)
  // > 0: distances in the similarity (eq. 8) are divided by this length (scene units; 1 is
  // the paper's literal form); 0: the scene's bounding radius over sqrt(3) (EnsembleParams).
  double ensemble_similarity_length = 0.0;
  // The anisotropic kernel's fallback when a fit is unusable: false, the paper's vMF about
  // the direction from the previous vertex; true, an isotropic Gaussian on the tangent plane
  // (the alternative the paper names).
  bool ensemble_plane_fallback = false;
  // How a step's Υ is chosen: false, by the counter (the paper's §3.1.1); true, the M paths
  // nearest the current path's image point (ensemble_guides.h).
  bool ensemble_nearby_guides = false;
  // The adaptive α from all of Y's image points (one α per swap) instead of the step's Υ.
  bool ensemble_alpha_from_ensemble = false;
  // > 0: the factor on the anisotropic path perturbation's fitted covariances; 0: its own.
  double ensemble_aniso_scale = 0.0;
  // < 1: the anisotropic kernels as scale mixtures of their fitted Gaussian, scales from this
  // to 1 (EnsembleParams::aniso_smallest_scale); 1: the paper's single Gaussian.
  double ensemble_aniso_smallest_scale = 1.0;
  // The geometry-aware (gamlt) perturbations' cones by the cheap conservative bound from the
  // clearance field instead of the exact hierarchy walk (mutations/geometry_aware/cone.h).
  bool gamlt_field_cone = false;
  // > 0 (the default): the gamlt cones memoised by quantised segments (cells of this fraction
  // of each segment's length) instead of computed for each segment's own endpoints (0, the
  // exact walk; mutations/geometry_aware/cone_cells.h). Exclusive with gamlt_field_cone.
  double gamlt_cone_cells = kGamltConeCell;
  // The cells' default size. 1/2: at the bench suite's sizes (1 thread, medians of 3
  // interleaved rounds) gamlt's chains took 1.17-1.45x MLT's time per mutation on the five
  // suite scenes and Bitterli's Veach Ajar with cells of 1/2, 1.11-1.70x with 1/4 and
  // 1.07-3.21x with the exact walk, while the chains' variance per mutation with cells of 1/2
  // matched the exact cones' (Cornell box 1.362e-3 against 1.383e-3, Veach Ajar 1.644 against
  // 1.670; docs/performance.md, "Memoised cones of quantised segments").
  static constexpr double kGamltConeCell = 1.0 / 2.0;
  // The manifold perturbation's step factor λ (mutations/manifold_perturbation.h; Mitsuba's
  // probFactor or lambda, whose default this is).
  double manifold_lambda = 50.0;
  // Its offset manifolds' typical change of a microfacet normal per move, in degrees (Mitsuba's
  // avgAngleChangeSurface; 1 is the guess Mitsuba starts from before it measures its own).
  // 0: rough vertices always end the perturbation's walks and chains.
  double manifold_angle_change = 1.0;
  // Delayed (two-stage) acceptance for proposals that defer part of their ratio (the gamlt
  // perturbations' ranges at y): y's cones only for proposals past the first stage
  // (include/emlt/mcmc/delayed_acceptance.h).
  bool gamlt_delayed_acceptance = false;
  // The anisotropic covariance as a reliability-weighted covariance (times 0.05) instead of
  // eq. 11 as printed.
  bool ensemble_aniso_weighted = false;

  // Receives images at power-of-two samples (mutations) per pixel; not owned. Null: none.
  SnapshotSink* snapshots = nullptr;
  std::string bdpt_strategies_dir;  // non-empty: bdpt also writes per-strategy images here
  // Checkpoints, stop signals and the state to resume from (render_control.h); not owned.
  // Null: the render runs to its budget unless interruption::request_stop() is called.
  RenderControl* control = nullptr;
};

inline const char* to_string(MisHeuristic h) {
  switch (h) {
    case MisHeuristic::Balance: return "balance";
    case MisHeuristic::Power: return "power";
    case MisHeuristic::Max: return "max";
    case MisHeuristic::SecondOrder: return "second-order";
  }
  return "power";
}

// --direct-sampler's words, the command line's and checkpoints' names of each set.
inline const char* direct_point_set_name(DirectPointSet p) {
  switch (p) {
    case DirectPointSet::Independent: return "independent";
    case DirectPointSet::Fibonacci: return "fibonacci";
    case DirectPointSet::Bmc: return "bmc";
    case DirectPointSet::Adaptive: return "adaptive";
    case DirectPointSet::Sobol: return "sobol";
    case DirectPointSet::LarcherPillichshammer: return "larcher-pillichshammer";
    case DirectPointSet::BlueNoise: return "blue-noise";
  }
  return "independent";
}
// The inverse; words it does not know (range-checked before) give Independent.
inline DirectPointSet direct_point_set_from_name(const std::string& name) {
  for (DirectPointSet p :
       {DirectPointSet::Fibonacci, DirectPointSet::Bmc, DirectPointSet::Adaptive,
        DirectPointSet::Sobol, DirectPointSet::LarcherPillichshammer, DirectPointSet::BlueNoise})
    if (name == direct_point_set_name(p)) return p;
  return DirectPointSet::Independent;
}

}  // namespace emlt
