#pragma once
// The Metropolis step of path-space MLT (mlt, gamlt, emlt), and what it splats into and
// counts.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "emlt/film/fixed_point_film.h"
#include "emlt/film/pixel_filter.h"
#include "emlt/integrators/mlt/mlt_chain.h"
#include "emlt/mcmc/alpha_tally.h"
#include "emlt/mcmc/strategy_mix.h"
#include "emlt/run/chain_sweeper.h"

namespace emlt {

// f*: the luminance of a path's contribution.
inline double luminance(const DVec3& c) {
  return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

// What one block of chains counts: its strategies' statistics. Blocks are a fixed partition
// of the chains, so the counters sum to the same bits on any thread count; kept per block
// rather than per chain because a chain visited for a single step (EMLT) would miss the
// cache on its own counters. Up to 256 blocks, so that with 16 threads each takes 16 per
// sweep and the last ones leave cores idle only briefly (greedy scheduling of measured block
// times: 0.95 of the ideal at 16 threads with 64 blocks, 0.99 with 256; docs/performance.md,
// "To 16 threads").
struct BlockOutput {
  std::vector<BlockCounter>& stats;  // the sweeper's (chain_sweeper.h)
  AlphaTally alpha;                  // the α of the block's guided linear steps (EMLT)
};

// Asks for a path's vertices ahead of use: EMLT visits each of its many chains for a single
// step, and the next chain's path is a separate allocation the hardware cannot guess.
void prefetch_path(const Path& path);

// The film pixel a path lands in.
size_t film_index(const Path& path, int width, int height);

// The film a chain splats into: its thread's (shared by several threads when there are more
// threads than films); likewise, when requested, the film of the image-plane moves of its
// proposals per pixel of the current path (sum dx^2, sum dy^2, count) for --aniso-map.
struct FilmSlot {
  FixedPointFilm& film;
  FixedPointFilm* moves;
  bool shared;
  const PixelFilter& filter;
  double scale = 1.0;  // on every splat's weight (ERPT's chains of another energy)
  // Out of line so that a profile of the chains (bench/suite.py, callgrind) can tell
  // splatting from the driver's bookkeeping; one call per splat, below 1 % of a mutation.
  [[gnu::noinline]] void splat(int width, int height, const Path& path, const DVec3& contribution,
                               double target, double weight) const;
};

// Takes the chain's remaining steps of the sweep (chain.sweep_left), or returns early, with
// every step it took complete, when an interruption is requested; returns the steps taken.
// How a step scores: with expected values (the proposal gets a, the current path 1 - a) or,
// as the chains of the original MLT papers, the state after the step with weight 1.
struct StepRules {
  bool ignore_selection = false;
  bool expected_values = true;
  bool drop_rejected_steps = false;  // an injected bug (MltOptions)
};

uint64_t run_chain(MltChain& chain, uint64_t chain_index, const StrategyMix& mix,
                   MutationContext ctx, const StepRules& rules, BlockOutput& out,
                   const FilmSlot& film, int width, int height);

}  // namespace emlt
