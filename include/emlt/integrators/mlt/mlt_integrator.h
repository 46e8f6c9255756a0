#pragma once
// Path-space Metropolis light transport (Veach & Guibas 1997). A bootstrap of BDPT
// samples gives b (the mean pixel luminance) and the chains' seeds; independent chains,
// each with its own random stream, then run Metropolis-Hastings on f* = luminance of the
// path contribution with strategies from mutations/. Every step splats the proposal with
// weight a and the current path with 1 - a (expected values); the image is scaled so that
// it estimates f itself: pixel = width * height * b / mutations * (sum of splats), each
// splat carrying F / f* (colour with luminance one).
//
// Ensemble mode (EMLT): the same chains, estimator and bootstrap, run as two halves that
// take turns; while one half (X) moves, the other (Y) is frozen and guides it
// (ensemble_guides.h). Each X step keeps f invariant for a fixed Y, so each half-sweep
// preserves the product density of both ensembles (paper §3).
//
// Determinism: chains are grouped in a fixed number of blocks, each with its own film,
// summed in block order; the schedule is a fixed number of rounds. The same seed and
// chain count give the same bits at any thread count.
#include "emlt/mcmc/alpha_tally.h"
#include "emlt/mcmc/ensemble_guides.h"
#include "emlt/mcmc/strategy_mix.h"
#include "emlt/run/integrator.h"

namespace emlt {

struct MltStatistics {
  // b as the image is scaled by it, from b_samples samples: in mlt, gamlt and emlt the
  // bootstrap's and those drawn beside the chains (normalisation_pass.h); in pssmlt and mmlt
  // the primary samples of the seeds' bootstrap and the chains' b_large_steps large steps
  // (pss_normalisation.h), which scale the chains' part of the image. The largest single
  // sample's share of b (0: not known).
  double b = 0.0, b_standard_error = 0.0, b_largest_share = 0.0;
  uint64_t b_samples = 0, b_large_steps = 0;
  // mmlt's: of b_samples, the BDPT samples split by length (the path-space bootstrap's and
  // those drawn beside the chains), each counted once though it adds to every length.
  uint64_t b_bidirectional_samples = 0;
  // The bootstrap's own b and samples.
  double bootstrap_b = 0.0;
  uint64_t bootstrap_samples = 0, chains = 0, mutations = 0;
  double seconds = 0.0;                // the whole render: direct pass, bootstrap and chains
  double direct_seconds = 0.0;         // the separate direct-lighting pass (--direct separate)
  int direct_spp = 0;                  // its samples per pixel (0 with --direct mlt)
  double bootstrap_seconds = 0.0;      // bootstrap and chain seeding
  double normalisation_seconds = 0.0;  // the samples drawn beside the chains
  // The strategies' searches built before the chains (Mutation::prepare: gamlt's surface
  // hierarchy and clearance field), in this run; not the chains' time.
  double prepare_seconds = 0.0;
  // What the seed pool is worth in equally weighted candidates (0 after a resume: not saved,
  // and then left out of --stats).
  double bootstrap_effective_candidates = 0.0;
  // Mutations per second of the chains alone (what the benchmark calls "chain only").
  double chain_mutations_per_second() const {
    const double chain_seconds =
        seconds - direct_seconds - bootstrap_seconds - prepare_seconds - normalisation_seconds;
    return chain_seconds > 0.0 ? double(mutations) / chain_seconds : 0.0;
  }
  std::vector<std::string> strategy_names;
  std::vector<StrategyStats> strategies;
  // Ensemble MLT only (ensemble_size 0 otherwise).
  uint64_t ensemble_size = 0, ensemble_neighbours = 0, ensemble_iterations = 0, swaps = 0;
  double tree_seconds = 0.0;  // rebuilding Y's path-type tree and α at the swaps
  // The linear kernels' α: averaged over the guided steps that drew one (over the swaps'
  // α when none did), and its distribution over those steps.
  double mean_alpha = 0.0;
  AlphaTally alpha;
};

// An integrator whose Markov chains report their figures after a render (b, chains, each
// strategy's acceptance), which --stats writes: mlt and its variants, pssmlt and mmlt, erpt.
class ChainStatisticsSource {
 public:
  virtual ~ChainStatisticsSource() = default;
  virtual const MltStatistics& chain_statistics() const = 0;
};

// Diagnostics and tests: a strategy mix built in code (instead of settings.mutations),
// and a switch that drops the selection-probability term from the acceptance ratio, to
// show that the tests notice.
// Steps per chain behind the default chain count (MltIntegrator::default_chain_count; its
// definition gives the measurements): many short chains for Veach's mix, fewer and longer
// ones for manifold exploration.
inline constexpr uint64_t kMltStepsPerChain = 64;
inline constexpr uint64_t kMemltStepsPerChain = 4096;

struct MltOptions {
  std::shared_ptr<const StrategyMix> mix;
  bool ignore_selection_probability = false;
  // Test switch: with settings.mlt_expected_values off, a rejected step adds nothing (the
  // current path loses the weight of the steps it stayed).
  bool drop_rejected_steps = false;
  // A named variant with its own default mix (used when settings.mutations is empty, i.e.
  // --mutations was not given): `--integrator gamlt` is this integrator named "gamlt" with
  // kGamltMix.
  std::string name = "mlt";
  std::string default_mix = kMltMix;
  // Ensemble MLT (Bashford-Rogers et al. 2021): the chains form two ensembles X and Y of
  // settings.ensemble_size paths; X takes `it` steps per path guided by the frozen Y, then
  // the two swap roles. `--integrator emlt` is this with kEmltMix.
  bool ensemble = false;
  EnsembleParams ensemble_params;
  // Without --chains, the budget's mutations over this many steps per chain is the chain
  // count (default_chain_count).
  uint64_t steps_per_chain = kMltStepsPerChain;
};

class MltIntegrator final : public Integrator, public ChainStatisticsSource {
 public:
  explicit MltIntegrator(MltOptions options = {}) : options_(std::move(options)) {}
  std::string name() const override { return options_.name; }
  RenderResult render(const Scene& scene, const RenderSettings& settings,
                      ProgressReporter& progress) const override;

  // Filled by the last render (printed by the command line, written by --stats).
  const MltStatistics& statistics() const { return stats_; }
  const MltStatistics& chain_statistics() const override { return stats_; }

  static int default_chain_count(uint64_t mutations, uint64_t steps_per_chain = kMltStepsPerChain);

 private:
  MltOptions options_;
  mutable MltStatistics stats_;
};

}  // namespace emlt
