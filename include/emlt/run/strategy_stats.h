#pragma once
// What the chains count per mutation strategy (the chain sweeper sums them over blocks and
// ranks; --stats and the convergence log report them).
#include <cstdint>

namespace emlt {

struct StrategyStats {
  uint64_t proposed = 0;        // times chosen
  uint64_t not_applicable = 0;  // steps where it had weight but did not apply to the path
  uint64_t failed = 0;          // proposals that could not be built (a = 0)
  uint64_t accepted = 0;
  uint64_t fallbacks = 0;       // guided strategies: steps that used the unguided fallback
  double acceptance_sum = 0.0;  // sum of a over proposals

  void merge(const StrategyStats& o) {
    proposed += o.proposed;
    not_applicable += o.not_applicable;
    failed += o.failed;
    accepted += o.accepted;
    fallbacks += o.fallbacks;
    acceptance_sum += o.acceptance_sum;
  }
  double mean_acceptance() const { return proposed ? acceptance_sum / double(proposed) : 0.0; }
};

}  // namespace emlt
