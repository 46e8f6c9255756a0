// The ensemble-informed variants beyond the paper (docs/experiments.md, "Beyond the
// paper"): the density jump (density_jump.h, strategies emlt-jump and emlt-jump-near, the
// latter weighing the guides by a vertex the move keeps) and the perturbations whose
// range is the spread of the frozen ensemble (spread_scaled_perturbation.h, emlt-spread-*).
//
// First each kernel alone on the analytic 2-D target of ensemble_kernel_test.cpp (design
// notes §6): chains started from exact draws of π must still be exact draws of π after the
// kernel's steps (χ²), and the injected bug must be detected. Υ is drawn for each step as 8
// consecutive entries of a frozen list of 64 draws of π, before the kernel looks at x, as
// the renderer draws it by (type, chain, step). Then each strategy, mixed with the
// bidirectional mutation and run by the ensemble driver, converges to BDPT on the Cornell box
// (and the spread-scaled caustic perturbation on the glass scene), and the jump without its
// density ratio visibly does not.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/mcmc/strategy_mix.h"
#include "mutations/ensemble/density_jump.h"
#include "mutations/ensemble/density_jump_lens.h"
#include "mutations/ensemble/guide_spread.h"
#include "mutations/perturbation_common.h"
#include "statistical/ensemble_kernel_harness.h"
#include "support/mlt_test_helpers.h"

namespace emlt {
namespace {

using namespace ensemble_test;

constexpr int kChains = 20000;
constexpr int kSteps = 24;
constexpr size_t kGuides = 8;

// Υ for one step: kGuides consecutive entries (cyclically) of the frozen list, the start
// drawn independently of the current state.
std::span<const Vec2> upsilon(const std::vector<Vec2>& frozen, Rng& rng) {
  const size_t start = rng.uniform_index(uint32_t(frozen.size() - kGuides + 1));
  return std::span<const Vec2>(frozen).subspan(start, kGuides);
}

enum class JumpWeights {
  Uniform,
  Kept,       // drawn before looking at x: stands for weights from a vertex the move keeps
  FromState,  // the injected bug: weights from the similarity of the moved state itself
};

struct JumpTestKernel {
  std::vector<Vec2> frozen;
  bool drop_ratio = false;
  JumpWeights weighting = JumpWeights::Uniform;

  Step<Vec2> operator()(const Vec2& x, Rng& rng) const {
    const auto guides = upsilon(frozen, rng);
    std::array<double, kGuides> weights{};
    for (size_t n = 0; n < kGuides; ++n) {
      const Vec2 d = guides[n] - x;
      weights[n] = weighting == JumpWeights::Kept ? 0.1 + rng.uniform_double()
                                                  : std::exp(-2.0 * double(glm::dot(d, d)));
    }
    const auto mixture = ensemble::fit_guide_mixture(guides, 0.05,
                                                     weighting == JumpWeights::Uniform
                                                         ? std::span<const double>()
                                                         : std::span<const double>(weights));
    const auto jump = ensemble::propose_jump(x, mixture, rng);
    return {jump.state, drop_ratio ? 0.0 : jump.log_density_ratio, true};
  }
};

// Veach's 1/r offset with r_max the spread of Υ: symmetric, so the log ratio is 0.
struct SpreadTestKernel {
  std::vector<Vec2> frozen;
  // The injected bug: a scale from the ensemble's local density at the current state (twice
  // the distance from x to its nearest guide) without the Hastings correction it needs.
  bool local_scale = false;

  Step<Vec2> operator()(const Vec2& x, Rng& rng) const {
    const auto guides = upsilon(frozen, rng);
    double r_max = ensemble::guide_spread(guides);
    if (local_scale) {
      double nearest = 1e30;
      for (const Vec2& g : guides) nearest = std::min(nearest, double(glm::length(g - x)));
      r_max = 2.0 * nearest;
    }
    r_max = std::max(r_max, 0.04);
    const Vec2 offset = perturbation::sample_image_offset(0.01f, float(r_max), rng.uniform2());
    return {x + offset, 0.0, true};
  }
};

template <class Kernel>
ChainReport run_plane(const char* label, const Kernel& kernel) {
  const PlaneMixture target = plane_target();
  const PlaneGrid grid;
  const auto probabilities =
      grid.probabilities([&](double x, double y) { return target.density(x, y); });
  return run_chains<Vec2>(
      label, target, kernel, [&](const Vec2& p) { return grid.cell_of(p.x, p.y); }, probabilities,
      kChains, kSteps);
}

TEST(EnsembleIdeaKernels, GuideSpreadIsThePerAxisStandardDeviation) {
  const std::vector<Vec2> points{{0.0f, 0.0f}, {2.0f, 0.0f}, {0.0f, 2.0f}, {2.0f, 2.0f}};
  // Mean (1, 1); squared distances 2 each: sqrt(8 / (2 * 3)).
  EXPECT_NEAR(ensemble::guide_spread(points), std::sqrt(8.0 / 6.0), 1e-12);
  EXPECT_EQ(ensemble::guide_spread(std::span<const Vec2>(points).first(1)), 0.0);
}

TEST(EnsembleIdeaKernels, GuideMixtureDensityIntegratesToOne) {
  const std::vector<Vec2> centres{{0.0f, 0.0f}, {1.0f, 0.5f}, {-0.5f, 2.0f}};
  const auto mixture = ensemble::fit_guide_mixture(centres, 0.05);
  EXPECT_GT(mixture.bandwidth, 0.05);
  const double integral = test::integrate_2d(
      [&](double x, double y) {
        return std::exp(ensemble::guide_mixture_log_density(mixture, Vec2(float(x), float(y))));
      },
      -6.0, 6.0, -6.0, 8.0, 64);
  EXPECT_NEAR(integral, 1.0, 1e-3);
  // Far from every centre the log density stays finite (log-sum-exp).
  EXPECT_TRUE(std::isfinite(ensemble::guide_mixture_log_density(mixture, Vec2(500.0f, 500.0f))));
}

TEST(EnsembleIdeaKernels, DensityJumpKeepsTarget) {
  JumpTestKernel kernel{frozen_guides<Vec2>(plane_target(), 64, 11)};
  expect_matches_target(run_plane("density jump", kernel));
}

TEST(EnsembleIdeaKernels, DensityJumpWithoutItsRatioIsDetected) {
  JumpTestKernel kernel{frozen_guides<Vec2>(plane_target(), 64, 11), true};
  expect_detected(run_plane("density jump, bug: no q ratio", kernel));
}

TEST(EnsembleIdeaKernels, WeightedDensityJumpKeepsTarget) {
  JumpTestKernel kernel{frozen_guides<Vec2>(plane_target(), 64, 13), false, JumpWeights::Kept};
  expect_matches_target(run_plane("weighted density jump", kernel));
}

TEST(EnsembleIdeaKernels, WeightsFromTheMovedStateAreDetected) {
  JumpTestKernel kernel{frozen_guides<Vec2>(plane_target(), 64, 13), false, JumpWeights::FromState};
  expect_detected(run_plane("weighted density jump, bug: weights from x", kernel));
}

TEST(EnsembleIdeaKernels, SpreadScaledPerturbationKeepsTarget) {
  SpreadTestKernel kernel{frozen_guides<Vec2>(plane_target(), 64, 12)};
  expect_matches_target(run_plane("spread-scaled 1/r", kernel));
}

TEST(EnsembleIdeaKernels, ScaleFromTheCurrentStateIsDetected) {
  SpreadTestKernel kernel{frozen_guides<Vec2>(plane_target(), 64, 12), true};
  expect_detected(run_plane("1/r, bug: scale from x's nearest guide", kernel));
}

// ---------------------------------------------------------------------------------------
// Rendered: the strategies with the bidirectional mutation, by the ensemble driver.

Image ensemble_image(const Scene& scene, std::shared_ptr<const StrategyMix> mix,
                     const std::string& mutations, double mpp, uint64_t seed = 7) {
  RenderSettings s = test::base_settings();
  s.seed = seed;
  s.mutations = mutations;
  s.mutations_per_pixel = mpp;
  s.bootstrap_samples = 50000;
  s.direct_spp = 4096;
  s.direct_separate = true;
  s.ensemble_size = 256;
  MltOptions options;
  options.name = "emlt";
  options.ensemble = true;
  options.mix = std::move(mix);
  return test::render(MltIntegrator(options), scene, s);
}

std::shared_ptr<const StrategyMix> jump_mix(bool drop_ratio, bool near = false) {
  auto mix = std::make_shared<StrategyMix>(StrategyMix::parse("bidir=1"));
  mix->add("emlt-jump", std::make_unique<DensityJumpLens>(near, drop_ratio), 4.0);
  return mix;
}

TEST(EnsembleIdeasUnbiased, DensityJumpConvergesOnTheCornellBoxAndItsBugIsCaught) {
  const auto scene = test::shipped_scene("cornell-box", 16);
  const Image reference = test::bdpt_reference(*scene, 4096);
  const auto correct =
      test::tile_deviation(ensemble_image(*scene, jump_mix(false), "", 2000), reference, 4);
  // Measured: 0.074 and 0.446.
  const auto buggy =
      test::tile_deviation(ensemble_image(*scene, jump_mix(true), "", 2000), reference, 4);
  std::printf("[ info     ] density jump: worst 4x4 tile %.4f (no q ratio: %.4f)\n", correct.worst,
              buggy.worst);
  EXPECT_LT(correct.worst, 0.08);
  EXPECT_NEAR(correct.scale, 1.0, 0.04);
  EXPECT_GT(buggy.worst, 0.15) << "density ratio dropped";
  // The weighted variant at twice the budget: its worst tile was 0.09 at 2,000 (seed 7,
  // similarity lengths of the scene's radius / sqrt(3)).
  const auto near =
      test::tile_deviation(ensemble_image(*scene, jump_mix(false, true), "", 4000), reference, 4);
  std::printf("[ info     ] density jump near x_l: worst 4x4 tile %.4f\n", near.worst);
  EXPECT_LT(near.worst, 0.08);
  EXPECT_NEAR(near.scale, 1.0, 0.04);
}

TEST(EnsembleIdeasUnbiased, SpreadScaledMixConvergesOnTheCornellBox) {
  // 2 x 2 tiles: measured 0.009. The worst of 4 x 4 tiles is noisier: seeds 8, 9 give 0.088
  // and 0.028 at 2000 mutations per pixel and 0.018 and 0.012 at 8000 (Veach's mix by the same
  // driver: 0.034, 0.042; 0.021, 0.017), seed 7 0.10 at both 2000 and 4000 (one early spike:
  // a seed's longer run continues its shorter one), so it is printed, not tested.
  const auto scene = test::shipped_scene("cornell-box", 16);
  const Image reference = test::bdpt_reference(*scene, 4096);
  const Image image = ensemble_image(
      *scene, nullptr, "bidir=3,emlt-spread-lens=2,emlt-spread-caustic=2,emlt-spread-multichain=2",
      4000);
  test::expect_converged_to(image, reference, 2, 0.04, 0.04);
  std::printf("[ info     ] spread-scaled mix: worst 4x4 tile %.4f\n",
              test::tile_deviation(image, reference, 4).worst);
}

TEST(EnsembleIdeasUnbiased, SpreadScaledCausticAndMultiChainConvergeThroughGlass) {
  const auto scene = test::shipped_scene("cornell-glass", 16);
  const Image reference = test::bdpt_reference(*scene, 2048);
  const Image image = ensemble_image(
      *scene, nullptr, "bidir=1,emlt-spread-lens=1,emlt-spread-caustic=2,emlt-spread-multichain=4",
      3000);
  test::expect_converged_to(image, reference, 2, 0.12, 0.05);
}

}  // namespace
}  // namespace emlt
