#pragma once
// MLT's start: N bidirectional samples estimate the normalisation b = integral of f*
// (the mean pixel luminance) and give every (s, t) path they form a weight, its
// MIS-weighted luminance. Chains start from candidates resampled in proportion to those
// weights, which removes start-up bias (Veach 1997, §11.3.1).
//
// Candidates are stored as (sample, s, t) only: a seed path is rebuilt by replaying its
// sample's random stream, so the pool costs 12 bytes a candidate however long its paths.
#include <cstdint>
#include <optional>
#include <vector>

#include "emlt/path/path.h"
#include "emlt/render/settings.h"

namespace emlt {

struct BootstrapParams {
  uint64_t seed = 1;
  int samples = 100000;
  int min_edges = 1, max_edges = 30;  // only paths with this many segments count
  int rr_depth = 5;
  MisHeuristic mis = MisHeuristic::Power;
  int threads = 0;
};

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
  std::vector<double> cumulative;  // running sum of candidate weights
  bool interrupted = false;        // a stop signal cut it short: not to be used

  bool empty() const { return candidates.empty() || !(b > 0.0); }
  // How many equally weighted candidates the pool is worth, (sum w)^2 / sum w^2: chains
  // seeded from it repeat candidates once their count nears this.
  double effective_candidates() const;
  // Candidate index for u in [0, 1), chosen in proportion to weight.
  size_t choose(double u) const;
};

Bootstrap run_bootstrap(const Scene& scene, const BootstrapParams& params);

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
