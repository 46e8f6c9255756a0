#pragma once
// MLT's start: N bidirectional samples estimate the normalisation b = integral of f*
// (the mean pixel luminance) and give every (s, t) path they form a weight, its
// MIS-weighted luminance. Chains start from candidates resampled in proportion to those
// weights, which removes start-up bias (Veach 1997, §11.3.1).
//
// Candidates are stored as (sample, s, t) only: a seed path is rebuilt by replaying its
// sample's random stream, so the pool costs 12 bytes a candidate however long its paths.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/path/path.h"
#include "emlt/settings/settings.h"

namespace emlt {

struct BootstrapParams {
  uint64_t seed = 1;
  int samples = 100000;
  int min_edges = 1, max_edges = 30;  // only paths with this many segments count
  int rr_depth = 5;
  MisHeuristic mis = MisHeuristic::Power;
  int threads = 0;

  // A render's: its seed, samples, depths and MIS, on its threads.
  static BootstrapParams of(const RenderSettings& settings, int min_edges, int max_edges,
                            int threads) {
    return {settings.start_seed(),
            settings.bootstrap_samples,
            min_edges,
            max_edges,
            settings.rr_depth,
            settings.mis,
            threads};
  }
};

// What a visitor sees of one strategy of a bidirectional sample: its subpaths (for joining
// the path: join_subpaths) and the MIS-weighted contribution. Returning false stops the
// enumeration.
using StrategyVisitor =
    std::function<bool(int s, int t, const Rgb& contribution, std::span<const PathVertex> light,
                       std::span<const PathVertex> camera_side)>;

// One bidirectional sample as the bootstrap draws it (every strategy (s, t) with paths of
// params' lengths, MIS-weighted), but from `rng` and with its camera subpath through
// `raster`: a pixel sample's, whose contributions are then in the same units as a bootstrap
// sample's (W_e of the whole film). Not reentrant for the visitor (a scratch per thread).
void enumerate_sample_at(const Scene& scene, const BootstrapParams& params, Rng& rng,
                         const Vec2& raster, const StrategyVisitor& visit);

struct BootstrapCandidate {
  uint32_t sample = 0;
  uint8_t s = 0, t = 0;
  float weight = 0.0f;  // luminance of the MIS-weighted contribution
};

struct Bootstrap {
  double b = 0.0;               // mean over samples of the summed candidate weights
  double standard_error = 0.0;  // of b
  uint64_t samples = 0;
  std::vector<BootstrapCandidate> candidates;
  std::vector<double> cumulative;       // running sum of candidate weights
  double sum = 0.0, sum_squares = 0.0;  // of the samples' summed weights (b's, for growing)
  double largest_sample = 0.0;          // the largest of them
  bool interrupted = false;             // a stop signal cut it short: not to be used

  bool empty() const { return candidates.empty() || !(b > 0.0); }
  // How many equally weighted candidates the pool is worth, (sum w)^2 / sum w^2: chains
  // seeded from it repeat candidates once their count nears this.
  double effective_candidates() const;
  // Candidate index for u in [0, 1), chosen in proportion to weight.
  size_t choose(double u) const;
};

// Samples [0, params.samples).
Bootstrap run_bootstrap(const Scene& scene, const BootstrapParams& params);
// Adds samples [pool.samples, total) to a pool drawn with the same params: the same
// candidates, in the same order, as a run over [0, total) at once (b may differ in its last
// bits, being summed in other groups). A stop signal marks the pool interrupted.
void grow_bootstrap(const Scene& scene, const BootstrapParams& params, uint64_t total,
                    Bootstrap& pool);

// The summed candidate weights of each of samples [first, last), the terms whose mean is b,
// in sample order to `each` (one thread; a stop signal is left to the caller).
void bootstrap_sample_totals(const Scene& scene, const BootstrapParams& params, uint32_t first,
                             uint32_t last, const std::function<void(double)>& each);

// The same samples split by path length: each sample's summed candidate weights of every
// length, params.min_edges first (params.max_edges - params.min_edges + 1 of them), in sample
// order to `each` (one thread). mmlt's b_k (pss_chains.h).
void bootstrap_sample_lengths(const Scene& scene, const BootstrapParams& params, uint32_t first,
                              uint32_t last,
                              const std::function<void(std::span<const double>)>& each);

// How many samples the pool should have, given what `samples` of them are worth
// (effective_candidates) and the chains they seed: chains seeded from a pool worth fewer
// candidates than chains restart from its few bright paths, and short chains keep that noise
// in the image (on the public door at 128 mutations per pixel, 70 % of the variance;
// docs/performance.md, "The pool's share, measured"). Grown until it is worth two candidates
// a chain, never beyond `cap`, never shrunk.
uint64_t grown_bootstrap_samples(uint64_t samples, double effective, uint64_t chains, uint64_t cap);

// The most samples a growing pool may reach (the `cap` above). A thirty-second of the
// planned mutations (UINT64_MAX: none planned): on the public door at 128 mutations per pixel
// about 390,000 samples, where 400,000 halved the variance at equal time
// (docs/performance.md, "The pool's share, measured"); `time_cap` (bootstrap_time_cap);
// never more than 16 times the first round's `samples`, nor a pool of more than 4 million
// candidates (80 MB) at the first round's `candidates` per sample; never fewer than `samples`.
uint64_t bootstrap_growth_cap(uint64_t samples, size_t candidates, uint64_t planned_mutations,
                              uint64_t time_cap);
// Under a time budget, the samples a fifth of it draws at the first round's pace (`samples`
// in `first_round_seconds`, taken as at least a millisecond); UINT64_MAX without a budget.
uint64_t bootstrap_time_cap(uint64_t samples, double time_limit_s, double first_round_seconds);

// The candidate's path, rebuilt from its sample's stream (densities filled in): its
// subpaths and its one connection.
std::optional<Path> rebuild_candidate(const Scene& scene, const BootstrapParams& params,
                                      const BootstrapCandidate& candidate);
// The same path by the definition: the sample's whole enumeration replayed up to the
// candidate's strategy (the tests' reference for rebuild_candidate; every connection of
// the sample is evaluated again, so it costs a bootstrap sample).
std::optional<Path> rebuild_candidate_by_enumeration(const Scene& scene,
                                                     const BootstrapParams& params,
                                                     const BootstrapCandidate& candidate);

}  // namespace emlt
