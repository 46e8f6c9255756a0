#pragma once
// The chains of primary-sample-space MLT (pssmlt, mmlt) as the chain sweeper drives them:
// Kelemen's step (pss_integrator.h), whole sweeps of equal steps per chain, the image they
// make, their checkpoint section and their statistics.
//
// The image is Kelemen's estimator split into its two halves, each in its own layer of the
// sweeper's films, because the b inside the splats' weights (the bootstrap's, b_w) is fixed
// before the chains while the b that scales the chains' part must keep converging. A
// contribution F at z with f*(z) has the weight F / (f*/b_w + p_L), which is both
// alpha b_w F / f* and (1 - alpha) F / p_L with alpha = (f*/b_w) / (f*/b_w + p_L):
//   - the chains' part: the expected-value splats of current and proposal (weights 1 - a
//     and a), alpha F / f* = F / (f* + p_L b_w) each, into layer 1 (for MMLT a layer per
//     length with chains); the chains' states have density f*/b, so this layer estimates
//     the integral of alpha F only when scaled by the true b: by b_k/N_k at the end, with b_k
//     the mean of f* over every independent primary sample so far (pss_normalisation.h),
//     for MMLT pooled with the path-space bootstrap's samples split by length and those
//     drawn beside the chains (normalisation_pass.h);
//   - the independent part: at large steps only, the proposal's (1 - alpha) F / p_L, the
//     same F / (f* + p_L b_w) times b_w, into layer 0, scaled by b_w/N: it estimates the
//     integral of (1 - alpha) F with uniform samples, whatever b is.
// Their sum is Kelemen's image when the final b is b_w, and unbiased for any b_w as the
// final b converges: b_w only chooses how the two halves share each path (alpha).
#include <cstdint>
#include <optional>
#include <vector>

#include "emlt/image/image.h"
#include "emlt/integrators/mlt/mcmc_run.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/integrators/mlt/normalisation_pass.h"
#include "emlt/integrators/pss/pss_chain.h"
#include "emlt/integrators/pss/pss_integrator.h"
#include "emlt/integrators/pss/pss_normalisation.h"
#include "emlt/run/chain_sweeper.h"

namespace emlt {

// The oldest checkpoint format (checkpoint_file.h) whose chains' section this reads: earlier
// ones summed the image's two parts into one film.
inline constexpr uint32_t kPssChainsOldestFormat = 6;
// mmlt's chains' section ends with its normalisation beside the chains from format 7 on.
inline constexpr uint32_t kMmltChainsOldestFormat = 7;

// What the bootstrap gave the chains: each length's normalisation b_k (b for PSSMLT) and
// chains, the sums of f* over each length's samples that seeded them (the start of the b
// the chains' part of the image is scaled by, pss_normalisation.h), and the figures of the
// statistics. Saved at the head of the chains' section.
struct PssBootstrap {
  std::vector<double> b_length;
  std::vector<int32_t> chains_of_length;
  std::vector<NormalisationSums> seeds;
  int chain_count = 0;
  double standard_error = 0.0;  // b's, from the path-space bootstrap

  void save(StateWriter& out, const MltStatistics& stats) const;
  // Throws StateError for a state that does not fit `lengths` path lengths.
  void load(StateReader& in, int lengths, MltStatistics& stats);
  // b, the sum of the b_k in length order.
  double b() const;
};

// What the render fixed before the chains.
struct PssSetup {
  const Scene& scene;
  const RenderSettings& settings;
  const PrimarySampleTracer& tracer;
  PssOptions options;
  int min_edges, max_edges;
  PssBootstrap bootstrap;
  // mmlt's: BDPT samples split by length, the path-space bootstrap's then those drawn beside
  // the chains, pooled with the large steps into each b_k. MMLT's f*_k picks one of k + 1
  // strategies, so the rare bright paths a strategy finds come k + 1 times rarer among its
  // large steps than in a BDPT sample, where every strategy of every length is evaluated.
  std::optional<NormalisationPass> normalisation;
};

class PssChains final : public ChainSteps {
 public:
  // The chains of every length, with their streams; `resumed_section` (null for a fresh
  // render) reads their state on from the saved bootstrap.
  PssChains(PssSetup setup, McmcRun& run, ProgressReporter& progress, MltStatistics& stats,
            StateReader* resumed_section);

  // This rank's chains [first, second), which a fresh render seeds (on the arena).
  std::pair<uint64_t, uint64_t> owned_chains() const { return {first_owned_, end_owned_}; }
  std::vector<PssChain>& chains() { return chains_; }
  tbb::task_arena& arena() { return sweeper_.arena(); }

  // Runs the chains to the end of the budget or a stop; fills the statistics.
  RenderResult render(const std::string& name);

  uint64_t done() const override { return steps_done_ * chain_count_; }
  uint64_t planned() const override;
  bool spent() const override { return steps_done_ >= planned_steps_; }
  uint64_t taken_before() const override;
  bool may_end_for_time() const override { return steps_done_ > 0; }
  bool in_sweep() const override { return sweep_active_; }
  bool keep_pace(uint64_t mutations) override {
    return !setup_.normalisation || setup_.normalisation->up_to(mutations);
  }
  void begin_sweep(uint64_t rounds) override;
  uint64_t sweep_end() const override;
  uint64_t sweep_block(int block, size_t film) override;
  bool behind() const override;
  void sweep_agreed(bool incomplete, std::span<const uint64_t> lengths) override;
  uint64_t& rounds() override { return rounds_; }
  uint64_t final_done() override;
  bool log_final(uint64_t done) override;
  Image compose(uint64_t done) override;
  void save(StateWriter& out) const override;

 private:
  void load(StateReader& in);
  void step(PssChain& chain, PssSample& proposal, FixedPointFilm& film,
            std::vector<BlockCounter>& stats) const;
  // The figures of b (pss_normalisation.h) into the statistics; returns each layer's
  // factor on b_w (1 for the independent part's layer 0, b_k / b_w,k for a chains' layer).
  std::vector<double> normalise();
  uint64_t first_chain_of(uint64_t block) const {
    return chain_count_ * block / uint64_t(block_count_);
  }

  PssSetup setup_;
  MltStatistics& stats_;
  int width_, height_;
  uint64_t pixels_;
  // The films' layers: 0 the independent part, then the chains' part of each length with
  // chains (PssChain::layer), in length order; each pixels_ wide.
  size_t layers_;
  std::vector<bool> has_chains_;  // by length index
  uint64_t chain_count_;
  int block_count_;
  double p_large_;
  size_t no_light_row_;
  std::vector<PssChain> chains_;
  ChainSweeper sweeper_;
  uint64_t first_owned_, end_owned_;
  // The schedule (begin_sweep()): the steps every chain has taken at the end of the last
  // whole sweep, the sweep under way (each chain takes steps up to sweep_end), the timed
  // sweeps' rounds, the steps of the log's last row, and its next row's mutations per pixel.
  uint64_t planned_steps_;
  uint64_t steps_done_ = 0, sweep_end_ = 0, rounds_ = 1;
  uint64_t logged_ = UINT64_MAX;
  uint8_t sweep_active_ = 0;
  uint64_t next_snapshot_ = 1;
  McmcRun& run_;
};

}  // namespace emlt
