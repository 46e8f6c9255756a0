#pragma once
// Path-space Metropolis light transport (Veach & Guibas 1997). A bootstrap of BDPT
// samples gives b (the mean pixel luminance) and the chains' seeds; independent chains,
// each with its own random stream, then run Metropolis-Hastings on f* = luminance of the
// path contribution with strategies from mutations/. Every step splats the proposal with
// weight a and the current path with 1 - a (expected values); the image is scaled so that
// it estimates f itself: pixel = width * height * b / mutations * (sum of splats), each
// splat carrying F / f* (colour with luminance one).
//
// Determinism: chains are grouped in a fixed number of blocks, each with its own film,
// summed in block order; the schedule is a fixed number of rounds. The same seed and
// chain count give the same bits at any thread count.
#include "emlt/mcmc/strategy_mix.h"
#include "emlt/render/integrator.h"

namespace emlt {

struct MltStatistics {
  double b = 0.0, b_standard_error = 0.0;
  uint64_t bootstrap_samples = 0, chains = 0, mutations = 0;
  double seconds = 0.0;
  std::vector<std::string> strategy_names;
  std::vector<StrategyStats> strategies;
};

// Diagnostics and tests: a strategy mix built in code (instead of settings.mutations),
// and a switch that drops the selection-probability term from the acceptance ratio, to
// show that the tests notice.
// The EMLT paper's MLT: the bidirectional mutation with probability 1/3, the three
// perturbations sharing the rest.
inline constexpr const char* kMltMix = "bidir=3,lens=2,caustic=2,multichain=2";
// Geometry-aware MLT (project issue 7): the bidirectional mutation with the geometry-aware
// perturbations (mutations/geometry_aware/ga_perturbations.h), in plain MLT's proportions.
inline constexpr const char* kGamltMix = "bidir=3,ga-lens=2,ga-caustic=2,ga-multichain=2";

struct MltOptions {
  std::shared_ptr<const StrategyMix> mix;
  bool ignore_selection_probability = false;
  // A named variant with its own default mix (used when settings.mutations is empty, i.e.
  // --mutations was not given): `--integrator gamlt` is this integrator named "gamlt" with
  // kGamltMix.
  std::string name = "mlt";
  std::string default_mix = kMltMix;
};

class MltIntegrator final : public Integrator {
 public:
  explicit MltIntegrator(MltOptions options = {}) : options_(std::move(options)) {}
  std::string name() const override { return options_.name; }
  RenderResult render(const Scene& scene, const RenderSettings& settings,
                      ProgressReporter& progress) const override;

  // Filled by the last render (printed by the command line, written by --stats).
  const MltStatistics& statistics() const { return stats_; }

  static int default_chain_count(uint64_t mutations);

 private:
  MltOptions options_;
  mutable MltStatistics stats_;
};

}  // namespace emlt
