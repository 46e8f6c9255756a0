#pragma once
// Bidirectional path tracing (Veach 1997, ch. 10) on the path layer (src/path/). Each pixel
// sample traces one camera subpath (its pixel's stream, as the path tracer does) and one
// light subpath, then evaluates every strategy (s, t) whose path has at most max_depth
// segments: s = 0 (the camera path hits an emitter or escapes to the sky), t = 1 (light
// tracing, splatted to the film), and all connections in between, weighted by the balance
// or power heuristic from the densities the vertices store. Russian roulette ends both
// walks. With RenderSettings::bdpt_strategies_dir set, the MIS-weighted contribution of
// each strategy with at most 5 segments is also written there as s<s>_t<t>.exr.
#include <vector>

#include "emlt/run/integrator.h"
#include "emlt/settings/render_option.h"

namespace emlt {

// Diagnostics and tests: restrict the strategies, or drop the MIS weights. An unweighted
// single strategy (s, t) is an unbiased estimator of the light carried by paths of
// s + t - 1 segments; only t = 1 unweighted is light tracing.
struct BdptOptions {
  bool mis = true;
  int only_s = -1;  // >= 0: only strategies with this many light vertices
  int only_t = -1;  // >= 1: only strategies with this many camera vertices
};

class BidirectionalPathTracer final : public Integrator {
 public:
  explicit BidirectionalPathTracer(BdptOptions options = {}) : options_(options) {}
  std::string name() const override { return "bdpt"; }
  RenderResult render(const Scene& scene, const RenderSettings& settings,
                      ProgressReporter& progress) const override;

  // Longest path (in segments) BDPT renders when max_depth is unlimited (-1): every
  // strategy of a path must be producible for the MIS weights to sum to one, so both
  // subpaths are capped; Russian roulette makes the truncation negligible.
  static constexpr int kUnlimitedDepth = 30;
  // Strategy images cover paths of at most this many segments.
  static constexpr int kMaxStrategyImageDepth = 5;

 private:
  BdptOptions options_;
};

// BDPT's own options (render_option.h): --bdpt-strategies.
const std::vector<RenderOption>& bdpt_options();

}  // namespace emlt
