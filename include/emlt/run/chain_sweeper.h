#pragma once
// The one loop of every integrator that renders with Markov chains (mlt, gamlt, emlt,
// pssmlt, mmlt). The integrator supplies its chains (ChainSteps): how a sweep's steps fall
// to them, one block's share of a sweep, the image they make and their checkpoint state;
// the sweeper owns everything else:
// - the budget: `--mpp` (the chains' schedule counts it) or `--time`, checked between
//   sweeps on rank 0's clock, with the timed sweeps' rounds doubled while sweeps are short;
// - the order: a fixed partition of the chains into blocks, run as TBB tasks and splatting
//   into fixed-point films (one per thread, up to 16), so the films' integer sums are the
//   same bits at any thread count;
// - the rank share (a contiguous range of the blocks on each rank) and the exact
//   reductions of films and block counters across ranks, so `mpirun -n R` gives the
//   one-process image and statistics;
// - the separate direct light (mcmc_run.h) and the chains' own paced work (keep_pace()) in
//   slices that keep pace with the chains, so that a render stopped at any moment has both
//   parts of the image, each normalised for the work done;
// - stops and checkpoints: the blocks return at a stop signal or a checkpoint falling due,
//   every rank agrees on what to do (interruption.h), and the state is saved
//   (render_control.h, mcmc_run.h) or the render ends with the image of the steps taken;
// - progress, the convergence log's snapshots (their time left out of the budget) and the
//   result's figures.
#include <tbb/task_arena.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "emlt/film/fixed_point_film.h"
#include "emlt/run/chain_frame.h"
#include "emlt/run/integrator.h"
#include "emlt/run/progress.h"
#include "emlt/run/strategy_stats.h"
#include "emlt/run/sweep_profile.h"

namespace emlt {

// The chains of an MCMC integrator, as the sweeper drives them. Every call but
// sweep_block() is made by one thread, at the same point of the loop on every rank.
class ChainSteps {
 public:
  virtual ~ChainSteps() = default;

  // Mutations of every rank's chains: done by the last whole sweep (or, after a stop inside
  // one, so far), and planned by the budget (the time budget alone: UINT64_MAX).
  virtual uint64_t done() const = 0;
  virtual uint64_t planned() const = 0;
  // Whether no more sweeps are to come: the budget is spent.
  virtual bool spent() const = 0;
  // The progress this rank's chains had made when the render began (a resumed render's),
  // in the unit sweep_block() counts.
  virtual uint64_t taken_before() const = 0;
  // Whether the time budget may end the render here, before a sweep (false: the chains get
  // a first sweep even when the bootstrap spent the time).
  virtual bool may_end_for_time() const { return true; }

  // Work besides the direct light that keeps pace with the mutations (path-space MLT's
  // normalisation, normalisation_pass.h), brought up to `mutations` (every rank's) before
  // the sweep that ends there; false when a stop cut it short. A collective call.
  virtual bool keep_pace(uint64_t mutations) {
    (void)mutations;
    return true;
  }

  // Whether a sweep is under way (a resumed render may be inside one).
  virtual bool in_sweep() const = 0;
  // Plans the next sweep; `rounds`: its size in a timed render, in the chains' own unit.
  virtual void begin_sweep(uint64_t rounds) = 0;
  // The mutations done (every rank's) when the sweep under way is complete.
  virtual uint64_t sweep_end() const = 0;
  // Before a sweep under way goes on in a resumed render.
  virtual void continue_sweep() {}
  // Runs block `block`'s chains of the sweep (blocks this rank owns only), splatting into
  // the sweeper's film `film` (shared with other threads when films_shared()); returns
  // early, with every step it took complete, when an interruption is requested. Returns the
  // steps taken. Called concurrently for distinct blocks.
  virtual uint64_t sweep_block(int block, size_t film) = 0;
  // Whether this rank's chains have steps of the sweep left (a stop cut it short).
  virtual bool behind() const = 0;
  // Lengths every rank is to know the maxima of with the decision that ends a sweep (EMLT's
  // exchange of paths under MPI); none by default.
  virtual std::vector<uint64_t> exchange_lengths() { return {}; }
  // After every rank agreed whether the sweep is complete, with the maxima of
  // exchange_lengths(): a complete sweep is ended (and its snapshots taken, through
  // ChainSweeper::snapshot()).
  virtual void sweep_agreed(bool incomplete, std::span<const uint64_t> lengths) = 0;
  // A timed sweep's rounds, doubled while sweeps are short when rounds_grow().
  virtual uint64_t& rounds() = 0;
  virtual bool rounds_grow() const { return true; }

  // After the last sweep: the mutations the image counts (every rank's; after a stop inside
  // a sweep, those taken), and whether the log is to end with a row of that image (false:
  // its last row already is it); a true answer counts the row as written.
  virtual uint64_t final_done() { return done(); }
  virtual bool log_final(uint64_t done) = 0;
  // The image after `done` mutations, the direct light so far (ChainFrame::direct_image())
  // and the chains', complete on rank 0 (a collective call).
  virtual Image compose(uint64_t done) = 0;
  // The chains' section of the checkpoint (mcmc_run.h).
  virtual void save(StateWriter& out) const = 0;
};

// A block's counter of one statistic, on cache lines of its own: blocks run on different
// cores.
struct alignas(64) BlockCounter : StrategyStats {};

class ChainSweeper {
 public:
  // `blocks`: the fixed partition of the chains, of which each rank owns a contiguous share;
  // `names`: the statistics each block counts (block_stats()); `layers`: images of `pixels`
  // each film holds one after another (pssmlt's parts of the image, scaled apart at the end).
  // The sweeper keeps references to settings, progress and run.
  ChainSweeper(const RenderSettings& settings, ProgressReporter& progress, ChainFrame& run,
               uint64_t pixels, int blocks, std::vector<std::string> names, size_t layers = 1);
  ~ChainSweeper();

  // The render's threads, and the arena that holds them (also for the integrator's own
  // parallel work, such as building EMLT's guides).
  static int thread_count(const RenderSettings& settings);
  int threads() const { return threads_; }
  tbb::task_arena& arena() { return *arena_; }

  int blocks() const { return blocks_; }
  // This rank's blocks [first, second).
  std::pair<uint64_t, uint64_t> owned_blocks() const { return owned_; }
  bool owns_block(uint64_t block) const { return block >= owned_.first && block < owned_.second; }

  // The films the blocks splat into (pixels x layers each); films_shared(): more threads
  // than films, so threads add atomically.
  std::vector<FixedPointFilm>& films() { return films_; }
  bool films_shared() const { return shared_films_; }
  // The films' sum as exact integers (this rank's); throws Error when a film overflowed.
  std::vector<int64_t> film_units() const;
  void load_film_units(const std::vector<int64_t>& units);

  // Block `block`'s counters of the statistics the sweeper was given the names of, which
  // the chains count as they step; a checkpoint keeps them (save_stats()).
  std::vector<BlockCounter>& block_stats(size_t block) { return stats_[block]; }
  void save_stats(StateWriter& out) const;
  void load_stats(StateReader& in);
  // Every block's counters merged in block order, on rank 0 (a collective call: a block's
  // counters are its owner's, the other ranks hold zeros, so the sums are exact).
  std::vector<StrategyStats> merged_stats() const;

  // Rank 0's value of a figure that depends on its clock, for every rank (a collective call
  // in a timed render under MPI; nothing to send otherwise).
  void root_decides(uint64_t& value) const;
  bool timed() const { return timed_; }

  // A row of the convergence log, the image after `done` mutations; its time is left out of
  // the budget and the reported seconds.
  void snapshot(ChainSteps& chains, uint64_t done);

  SweepProfile& profile() { return profile_; }

  // Sweeps until the budget is spent or every rank agrees to stop, saving a checkpoint at
  // every pause and when the budget is done. The result's image is the chains' (complete
  // on rank 0), with its figures; the integrator adds its statistics.
  RenderResult run(ChainSteps& chains, const std::string& label);

 private:
  void snapshot_image(uint64_t done, const Image& image);
  double direct_share(const ChainSteps& chains) const;

  const RenderSettings& settings_;
  ProgressReporter& progress_;
  ChainFrame& run_;
  uint64_t pixels_;
  int threads_;
  std::unique_ptr<tbb::task_arena> arena_;
  int blocks_;
  std::pair<uint64_t, uint64_t> owned_;
  std::vector<std::string> names_;
  std::vector<std::vector<BlockCounter>> stats_;
  std::vector<FixedPointFilm> films_;
  bool shared_films_;
  bool timed_;
  SweepProfile profile_;
};

}  // namespace emlt
