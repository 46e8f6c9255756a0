#pragma once
// The chains of path-space MLT (mlt, gamlt, emlt) as the chain sweeper drives them: how a
// sweep's mutations fall to the chains (all of them in MLT, a half-ensemble in EMLT), the
// image they make, their checkpoint section, and the statistics they leave.
#include <cstdint>
#include <memory>
#include <vector>

#include "emlt/image/image.h"
#include "emlt/integrators/mlt/ensemble_schedule.h"
#include "emlt/integrators/mlt/mcmc_run.h"
#include "emlt/integrators/mlt/mlt_chain.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/integrators/mlt/mlt_step.h"
#include "emlt/integrators/mlt/normalisation_pass.h"
#include "emlt/run/chain_sweeper.h"

namespace emlt {

// What the render fixed before the chains.
struct MltSetup {
  const Scene& scene;
  const RenderSettings& settings;
  const StrategyMix& mix;
  MutationContext ctx;
  StepRules rules;
  uint64_t planned;                            // mutations (UINT64_MAX: the time budget alone)
  std::unique_ptr<EnsembleSchedule> ensemble;  // EMLT only
  NormalisationPass normalisation;  // started from the bootstrap (a resumed one is loaded)
};

class MltChains final : public ChainSteps {
 public:
  // The head of a saved chains' section: the bootstrap's figures (into stats) and the
  // chains, each but its `applicable`. Throws StateError for a state that does not fit
  // (`ensemble_chains`: EMLT's chain count, 0 for MLT).
  static std::vector<MltChain> load_chains(StateReader& in, const PathCodec& codec,
                                           MltStatistics& stats, uint64_t ensemble_chains);

  // `chains`: seeded, or loaded with load_chains() (then `resumed_section` reads on where
  // that left off).
  MltChains(MltSetup setup, std::vector<MltChain> chains, McmcRun& run, ProgressReporter& progress,
            MltStatistics& stats, StateReader* resumed_section);

  // Runs the chains to the end of the budget or a stop; fills the statistics.
  RenderResult render(const std::string& name);

  uint64_t done() const override { return done_; }
  uint64_t planned() const override { return setup_.planned; }
  bool spent() const override { return done_ >= setup_.planned; }
  uint64_t taken_before() const override { return done_; }
  bool in_sweep() const override { return sweep_.active; }
  void begin_sweep(uint64_t rounds) override;
  uint64_t sweep_end() const override { return sweep_.done_before + sweep_.size; }
  bool keep_pace(uint64_t mutations) override { return setup_.normalisation.up_to(mutations); }
  void continue_sweep() override;
  uint64_t sweep_block(int block, size_t film) override;
  bool behind() const override { return steps_left() > 0; }
  std::vector<uint64_t> exchange_lengths() override;
  void sweep_agreed(bool incomplete, std::span<const uint64_t> lengths) override;
  uint64_t& rounds() override { return timed_rounds_; }
  bool rounds_grow() const override { return !setup_.ensemble; }
  bool log_final(uint64_t done) override;
  Image compose(uint64_t done) override;
  void save(StateWriter& out) const override;

 private:
  void load(StateReader& in);
  bool owns_chain(uint64_t c) const;
  uint64_t steps_left() const;
  void finish_statistics();

  MltSetup setup_;
  std::vector<MltChain> chains_;
  MltStatistics& stats_;
  const PathCodec codec_;
  int width_, height_;
  uint64_t pixels_;
  uint64_t chain_count_;
  bool timed_;
  bool record_moves_;
  ChainSweeper sweeper_;
  std::vector<BlockOutput> blocks_;
  // Moves are tallied in pixels^2 at 2^-8: a pixel holds 3.6e16, some 1e10 proposals that
  // cross a 4K image from it.
  std::vector<FixedPointFilm> move_films_;
  uint64_t first_owned_chain_, end_owned_chain_;
  // The sweep under way: chains [first, first + count) take `size` steps between them
  // (chain.sweep_left each), `done_before` counting the mutations before it.
  struct Sweep {
    uint8_t active = 0;
    uint64_t first = 0, count = 0, size = 0, done_before = 0;
  } sweep_;
  uint64_t done_ = 0, next_checkpoint_ = 1, timed_rounds_ = 1;
  uint64_t round_size_;
  // Chains with a seed (all, in practice): counted once every rank has them.
  uint64_t live_ = 0;
  McmcRun& run_;
  bool resumed_;
};

}  // namespace emlt
