#pragma once
// Primary-sample-space Metropolis light transport, in two forms:
//   - "pssmlt": Kelemen et al. 2002. Each chain's state is a vector of unit-cube
//     coordinates that drives a path tracer or BDPT (--pss-tracer pt|bdpt); a step is a
//     large step (every coordinate afresh) with probability --large-step, else a small one
//     (each coordinate perturbed, --pss-sigma); f* = the luminance of all the sample's
//     contributions.
//   - "mmlt": Hachisuka et al. 2014, Multiplexed MLT. Each chain keeps one path length k;
//     a coordinate picks the BDPT strategy, f*_k = the luminance of that strategy's
//     MIS-weighted contribution over its selection probability, and the chains of length k
//     are normalised by b_k, the image's mean luminance in paths of k segments.
// Both use Kelemen's combined estimator: every step splats the proposal y with weight
// (a + L) / (f*(y) / b + p_L) and the current state x with (1 - a) / (f*(x) / b + p_L),
// L = 1 for a large step; it is unbiased for any b > 0 and p_L, and with p_L = 0 reduces to
// the plain MLT estimator b F / f*. Its two halves, the chains' (a, 1 - a) and the large
// steps' (L), are kept apart, so that the chains' half is scaled by a b that keeps
// converging with the render while the weights keep the bootstrap's (pss_chains.h).
//
// MLT's bootstrap (BDPT samples) gives the weights' b (b_k), N independent primary samples
// the chains' seeds (resampled in proportion to f*, so there is no start-up bias) and the
// start of the converging b (pss_normalisation.h); the chains
// (pss_chains.h) run on the chain sweeper (chain_sweeper.h), as MLT's do, in a fixed
// partition of 64 blocks, taking whole sweeps of equal steps, so a seed gives the same bits
// at any thread or rank count and across a stop and resume. The direct light may be
// rendered separately (--direct separate) as for MLT.
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/integrators/pss/primary_sample_tracer.h"
#include "emlt/run/integrator.h"

namespace emlt {

// Tests: each switch injects a known mistake, to show that the tests notice it.
struct PssOptions {
  bool multiplexed = false;                 // mmlt; otherwise pssmlt
  bool drop_large_step_weight = false;      // the proposal's weight a instead of a + L
  bool keep_coordinate_on_reject = false;   // coordinate 0 not restored on rejection
  bool ignore_technique_selection = false;  // MMLT: no division by 1 / (k + 1)
  bool scale_by_bootstrap_b = false;        // the chains' part scaled by the bootstrap's b
  // Not a mistake: the bootstrap's b (b_k) times this, as a bootstrap that far off would
  // give, to show that the image no longer depends on it.
  double bootstrap_b_factor = 1.0;
  // mmlt's b_k from the chains' large steps (and the seeds') alone, as pssmlt's b: without
  // the path-space bootstrap's samples split by length and those drawn beside the chains
  // (pss_chains.h). An ablation of the measurement in docs/normalisation.md.
  bool mmlt_b_from_large_steps_only = false;
};

class PssMltIntegrator final : public Integrator, public ChainStatisticsSource {
 public:
  explicit PssMltIntegrator(PssOptions options = {}) : options_(options) {}
  std::string name() const override { return options_.multiplexed ? "mmlt" : "pssmlt"; }
  RenderResult render(const Scene& scene, const RenderSettings& settings,
                      ProgressReporter& progress) const override;
  // Filled by the last render: strategies "large" and "small" (step kinds), then "length k"
  // per path length (their proposals and acceptances): for MMLT the chain's length, for
  // PSSMLT the proposal's longest contributing path, and "no light" for a proposal without
  // any.
  const MltStatistics& statistics() const { return stats_; }
  const MltStatistics& chain_statistics() const override { return stats_; }

 private:
  PssOptions options_;
  mutable MltStatistics stats_;
};

}  // namespace emlt
