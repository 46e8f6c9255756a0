// EMLT's nearby Υ (ensemble_guides.h) tested without rendering, as the kernels are in
// ensemble_kernel_test.cpp: frozen guides drawn from a known 2-D target, sorted along the
// Hilbert curve (raster_order.h); each step's Υ is the window of M guides centred on the
// current state, α is §3.4's sigmoid of that window's bounding box, one guide is drawn in
// proportion to its similarity, and the linear kernel stretches about it. Υ and α are then
// functions of the state, so the reverse move is evaluated against the proposal's own Υ:
//     log a = log pi(y)/pi(x) + log lambda (the stretch's Jacobian)
//           + log g_{alpha(y)}(1/lambda) - log g_{alpha(x)}(1/lambda)
//           + log P(n | y, Υ(y)) - log P(n | x, Υ(x)),
// and a guide that Υ(y) does not hold cannot be chosen back: the move is rejected. Chains
// started from exact draws of pi must stay pi-distributed (chi-square of their final
// states); each way of getting the reverse move wrong must be detected.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "emlt/mcmc/adaptive_alpha.h"
#include "emlt/mcmc/raster_order.h"
#include "statistical/ensemble_kernel_harness.h"

using namespace emlt;
using namespace emlt::ensemble;
using namespace emlt::ensemble_test;

namespace {

constexpr int kChains = 20000;
constexpr int kSteps = 24;
// The target's plane [-4, 4]^2 laid on a film of 8 x 8 "pixels".
constexpr int kFilm = 8;
constexpr float kOffset = 4.0f;

enum class Injected {
  None,
  ReverseWithForwardGuides,  // P(n | y) and α(y) from x's Υ
  AlphaNotReversed,          // the reverse stretch density with x's α
  GuideIndexNotMapped,       // guide n of Υ(x) taken as entry n of Υ(y)
};

struct NearbyLinearKernel {
  std::vector<Vec2> sorted;    // the guides in curve order
  std::vector<uint64_t> keys;  // their curve positions
  size_t m = 8;
  SimilarityParams similarity{kPaperSimilarityEpsilon, 0.5};
  Injected bug = Injected::None;
  std::vector<double> log_weights_x, log_weights_y;

  static Vec2 raster(const Vec2& p) { return p + Vec2(kOffset); }
  size_t window_start(const Vec2& p) const {
    return centred_window_start(keys, raster_order_key(raster(p), kFilm, kFilm), m);
  }
  std::span<const Vec2> window(size_t start) const {
    return std::span<const Vec2>(sorted).subspan(start, std::min(m, sorted.size()));
  }
  static double alpha_of(std::span<const Vec2> guides) {
    std::vector<Vec2> rasters;
    for (const Vec2& g : guides) rasters.push_back(raster(g));
    return adaptive_alpha(image_coverage(rasters, kFilm, kFilm));
  }

  Step<Vec2> operator()(const Vec2& x, Rng& rng) {
    const size_t start_x = window_start(x);
    const std::span<const Vec2> guides_x = window(start_x);
    const StretchParams stretch_x{alpha_of(guides_x), StretchDistribution::InverseSqrt};
    log_weights_x.resize(guides_x.size());
    log_similarities_to_guides(x, guides_x, similarity, log_weights_x);
    const GuideChoice choice = choose_guide(log_weights_x, rng);
    const LinearProposal proposal = propose_linear(x, guides_x[choice.index], stretch_x, rng);
    if (!proposal.valid) return {x, 0.0, false};
    const Vec2 y = proposal.state;

    const bool forward_guides = bug == Injected::ReverseWithForwardGuides;
    const size_t start_y = forward_guides ? start_x : window_start(y);
    const std::span<const Vec2> guides_y = window(start_y);
    const long index_y = bug == Injected::GuideIndexNotMapped
                             ? long(choice.index)
                             : long(start_x + choice.index) - long(start_y);
    if (index_y < 0 || size_t(index_y) >= guides_y.size()) return {x, 0.0, false};
    const StretchParams stretch_y{alpha_of(guides_y), StretchDistribution::InverseSqrt};
    double log_ratio = proposal.log_density_ratio;
    if (bug != Injected::AlphaNotReversed)
      log_ratio += stretch_reverse_correction(proposal.lambda, stretch_x, stretch_y);
    log_weights_y.resize(guides_y.size());
    log_similarities_to_guides(y, guides_y, similarity, log_weights_y);
    log_ratio += guide_log_probability(log_weights_y, size_t(index_y)) - choice.log_probability;
    return {y, log_ratio, std::isfinite(log_ratio)};
  }
};

NearbyLinearKernel nearby_kernel(int guide_count, Injected bug) {
  const PlaneMixture target = plane_target();
  std::vector<Vec2> guides = frozen_guides<Vec2>(target, guide_count, 2);
  std::vector<uint64_t> key_of;
  for (const Vec2& g : guides)
    key_of.push_back(raster_order_key(NearbyLinearKernel::raster(g), kFilm, kFilm));
  std::vector<size_t> order(guides.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return key_of[a] != key_of[b] ? key_of[a] < key_of[b] : a < b;
  });
  NearbyLinearKernel kernel;
  for (size_t i : order) {
    kernel.sorted.push_back(guides[i]);
    kernel.keys.push_back(key_of[i]);
  }
  kernel.bug = bug;
  return kernel;
}

ChainReport run_nearby(const char* label, int guide_count, Injected bug) {
  const PlaneMixture target = plane_target();
  const PlaneGrid grid;
  const auto probabilities =
      grid.probabilities([&](double x, double y) { return target.density(x, y); });
  return run_chains<Vec2>(
      label, target, nearby_kernel(guide_count, bug),
      [&](const Vec2& p) { return grid.cell_of(p.x, p.y); }, probabilities, kChains, kSteps);
}

}  // namespace

// With 40 guides a window of 8 spans a fifth of them: α takes values across the sigmoid
// (checked below), so a wrong reverse α shows.
TEST(NearbyGuides, AlphaOfTheWindowsSpansTheSigmoid) {
  const NearbyLinearKernel kernel = nearby_kernel(40, Injected::None);
  double low = 1.0, high = 0.0;
  for (size_t s = 0; s + kernel.m <= kernel.sorted.size(); ++s) {
    const double alpha = NearbyLinearKernel::alpha_of(kernel.window(s));
    low = std::min(low, alpha);
    high = std::max(high, alpha);
  }
  EXPECT_LT(low, 0.2);
  EXPECT_GT(high, 0.35);
}

TEST(NearbyGuides, LinearKernelKeepsTarget) {
  expect_matches_target(run_nearby("nearby linear, 40 guides", 40, Injected::None));
  expect_matches_target(run_nearby("nearby linear, 400 guides", 400, Injected::None));
}
TEST(NearbyGuides, ReverseAgainstTheForwardGuidesIsDetected) {
  expect_detected(run_nearby("nearby linear, bug: reverse with x's guides", 40,
                             Injected::ReverseWithForwardGuides));
}
TEST(NearbyGuides, ReverseWithTheForwardAlphaIsDetected) {
  expect_detected(
      run_nearby("nearby linear, bug: reverse with x's alpha", 40, Injected::AlphaNotReversed));
}
TEST(NearbyGuides, GuideIndexNotMappedIsDetected) {
  expect_detected(
      run_nearby("nearby linear, bug: guide index not mapped", 40, Injected::GuideIndexNotMapped));
}
