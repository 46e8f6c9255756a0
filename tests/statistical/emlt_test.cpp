// Ensemble MLT rendered end to end: each guided strategy, mixed with the bidirectional
// mutation and run by the two-ensemble driver, converges to the BDPT reference; each
// injected bug (a dropped reverse density, Σ not refitted for the reverse move, the guide
// selection probability ignored, Υ chosen anew for the proposed path) visibly does not;
// and a seed gives the same bits on any thread count. The kernels' density ratios alone
// are checked against analytic targets in ensemble_kernel_test.cpp.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/mcmc/strategy_mix.h"
#include "mutations/ensemble/anisotropic_path.h"
#include "mutations/ensemble/environment_perturbation.h"
#include "mutations/ensemble/guided_caustic.h"
#include "mutations/ensemble/guided_lens.h"
#include "mutations/ensemble/guided_multichain.h"
#include "support/mlt_test_helpers.h"

namespace emlt {
namespace {

using test::bdpt_reference;
using test::expect_converged_to;
using test::shipped_scene;

struct EmltRun {
  std::shared_ptr<const StrategyMix> mix;  // null: settings.mutations
  std::string mutations = kEmltMix;
  double mpp = 2000;
  int ensemble_size = 256;
  int threads = 2;
  uint64_t seed = 7;
  bool direct_separate = true;
  double alpha = 0.0;  // > 0: a fixed α for the linear kernels instead of the adaptive one
  int max_depth = 0;   // > 0: instead of base_settings()'s
  int neighbours = 0;  // > 0: M instead of the default
  bool nearby = false;  // Υ near the path's image point instead of the counter's
  double aniso_smallest_scale = 1.0;  // < 1: the anisotropic kernels' scale mixture
};

Image emlt_image(const Scene& scene, const EmltRun& run, MltStatistics* stats = nullptr) {
  RenderSettings s = test::base_settings();
  s.mutations = run.mutations;
  s.mutations_per_pixel = run.mpp;
  s.bootstrap_samples = 50000;
  s.direct_spp = 4096;
  s.direct_separate = run.direct_separate;
  s.ensemble_size = run.ensemble_size;
  s.threads = run.threads;
  s.seed = run.seed;
  if (run.max_depth > 0) s.max_depth = run.max_depth;
  s.ensemble_neighbours = run.neighbours;
  MltOptions options;
  options.name = "emlt";
  options.ensemble = true;
  options.mix = run.mix;
  if (run.nearby) options.ensemble_params.selection = GuideSelection::Nearby;
  options.ensemble_params.aniso_smallest_scale = run.aniso_smallest_scale;
  if (run.alpha > 0.0) {
    options.ensemble_params.adaptive_alpha = false;
    options.ensemble_params.alpha_fixed = run.alpha;
  }
  const MltIntegrator emlt(options);
  Image image = test::render(emlt, scene, s);
  if (stats) *stats = emlt.statistics();
  return image;
}

// bidir=1 plus `strategy` with weight `weight`.
std::shared_ptr<const StrategyMix> with_bidir(std::unique_ptr<Mutation> strategy, double weight) {
  auto mix = std::make_shared<StrategyMix>(StrategyMix::parse("bidir=1"));
  const std::string name(strategy->name());
  mix->add(name, std::move(strategy), weight);
  return mix;
}

const StrategyStats& stats_of(const MltStatistics& stats, const std::string& name) {
  for (size_t i = 0; i < stats.strategy_names.size(); ++i)
    if (stats.strategy_names[i] == name) return stats.strategies[i];
  static const StrategyStats none;
  ADD_FAILURE() << "no strategy " << name;
  return none;
}

// Relative deviation of the luminance of blocks x blocks tiles from the reference's, after
// dividing out the global scale (b's error): the root mean square over the tiles.
double tile_deviation(const Image& image, const Image& reference, int blocks) {
  const auto luminance = [](const Rgb& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
  const int tile = image.width / blocks;
  std::vector<double> a, b;
  double ta = 0.0, tb = 0.0;
  for (int by = 0; by < blocks; ++by)
    for (int bx = 0; bx < blocks; ++bx) {
      double sa = 0.0, sb = 0.0;
      for (int y = by * tile; y < (by + 1) * tile; ++y)
        for (int x = bx * tile; x < (bx + 1) * tile; ++x) {
          sa += luminance(image.at(x, y));
          sb += luminance(reference.at(x, y));
        }
      a.push_back(sa);
      b.push_back(sb);
      ta += sa;
      tb += sb;
    }
  double squares = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = a[i] / (b[i] * ta / tb) - 1.0;
    squares += d * d;
  }
  return std::sqrt(squares / double(a.size()));
}

TEST(EmltUnbiased, FullMixConvergesToBdptOnTheCornellBox) {
  const auto scene = shipped_scene("cornell-box", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  MltStatistics stats;
  const Image image = emlt_image(*scene, {}, &stats);
  EXPECT_EQ(stats.ensemble_size, 256u);
  EXPECT_GT(stats.swaps, 100u);
  for (const char* name : {"emlt-lens", "emlt-caustic", "emlt-aniso"}) {
    EXPECT_GT(stats_of(stats, name).accepted, 10000u) << name;
    EXPECT_LT(stats_of(stats, name).fallbacks, stats_of(stats, name).proposed / 10) << name;
  }
  expect_converged_to(image, reference, 2, 0.06, 0.04);
  // Finer: 4 x 4 tiles (measured 0.02; the lens bugs below give 0.075 and more).
  EXPECT_LT(tile_deviation(image, reference, 4), 0.04);
}

// Each mix converges to BDPT on the shipped scene (16 x 16): 2 x 2 tiles within
// tile_tolerance and, when fine_tolerance > 0, the 4 x 4 tiles' deviation below it. With
// `seeds` > 1 the image is the mean of that many renders with consecutive seeds from
// run.seed, each of run.mpp / seeds mutations per pixel.
void expect_mixes_converge(const char* scene_name, std::initializer_list<const char*> mixes,
                           EmltRun run, double tile_tolerance, double total_tolerance,
                           double fine_tolerance = 0.0, int seeds = 1) {
  const auto scene = shipped_scene(scene_name, 16);
  const Image reference = bdpt_reference(*scene, 4096);
  const uint64_t first_seed = run.seed;
  run.mpp /= seeds;
  for (const char* mix : mixes) {
    SCOPED_TRACE(mix);
    run.mutations = mix;
    Image image;
    for (int k = 0; k < seeds; ++k) {
      run.seed = first_seed + uint64_t(k);
      const Image one = emlt_image(*scene, run);
      if (k == 0) image = Image(one.width, one.height);
      for (size_t i = 0; i < one.pixels.size(); ++i)
        image.pixels[i] += one.pixels[i] / float(seeds);
    }
    expect_converged_to(image, reference, 2, tile_tolerance, total_tolerance);
    if (fine_tolerance > 0.0) {
      EXPECT_LT(tile_deviation(image, reference, 4), fine_tolerance);
    }
  }
}

// With Υ near the path (--ensemble-guides nearby) every guided strategy evaluates its reverse
// move against the proposal's own Υ: the full mix and the presets converge all the same.
TEST(EmltUnbiased, NearbyGuidesConvergeOnTheCornellBox) {
  EmltRun run;
  run.mpp = 3000;
  run.nearby = true;
  expect_mixes_converge("cornell-box", {kEmltMix, "emlt-ani", "emlt-lin"}, run, 0.06, 0.04, 0.04,
                        3);
}

// The anisotropic kernels as scale mixtures (--ensemble-aniso-multiscale): image and world
// Gaussians sampled and evaluated as mixtures, alone and in the full mix.
TEST(EmltUnbiased, AnisotropicScaleMixtureConvergesOnTheCornellBox) {
  EmltRun run;
  run.mpp = 3000;
  run.aniso_smallest_scale = 0.01;
  expect_mixes_converge("cornell-box", {"emlt-ani", kEmltMix}, run, 0.06, 0.04, 0.04, 3);
}

TEST(EmltUnbiased, AnisotropicAndLinearPresetsConvergeOnTheCornellBox) {
  // Three seeds of 1,000 mutations per pixel each: the anisotropic kernel's 4 x 4 tile
  // deviation is heavy-tailed from one seed to the next (0.017-0.056 over 16 single seeds
  // of 2,000, two of them above 0.04), where the mean of three keeps a margin.
  EmltRun run;
  run.mpp = 3000;
  expect_mixes_converge("cornell-box", {"emlt-ani", "emlt-lin"}, run, 0.06, 0.04, 0.04, 3);
}

TEST(EmltUnbiased, FullMixAndPresetsConvergeOnTheDoorScene) {
  // The same tolerance as plain MLT's at this budget (geometry_aware_test.cpp), on the mean
  // of two seeds of 4,000 mutations per pixel each: a single seed's worst 2 x 2 tile is
  // heavy-tailed on this scene (emlt-lin, seeds 1-8: 0.035-0.18, seed 6 above 0.15), the
  // mean of two 0.03-0.095 (8 pairs).
  EmltRun run;
  run.mpp = 8000;
  expect_mixes_converge("door-ajar", {kEmltMix, "emlt-ani", "emlt-lin"}, run, 0.15, 0.05, 0.0, 2);
}

TEST(EmltUnbiased, CausticAndMultiChainConvergeThroughGlass) {
  const auto scene = shipped_scene("cornell-glass", 16);
  const Image reference = bdpt_reference(*scene, 2048);
  EmltRun run;
  run.mutations = "bidir=1,emlt-lens=1,emlt-caustic=2,emlt-multichain=4";
  run.mpp = 3000;
  MltStatistics stats;
  const Image image = emlt_image(*scene, run, &stats);
  EXPECT_GT(stats_of(stats, "emlt-multichain").accepted, 1000u);
  expect_converged_to(image, reference, 2, 0.12, 0.05);
}

TEST(EmltUnbiased, EnvironmentPerturbationConvergesForSkyLitDirectLight) {
  // Paper §4.3: guided lens + environment perturbation on environment-lit direct light.
  const auto scene = shipped_scene("env-sky", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  EmltRun run;
  run.mutations = "bidir=1,emlt-lens=1,emlt-env=2";
  run.direct_separate = false;
  // 4000 mutations per pixel: at 2000 the worst of the 2 x 2 tiles sat at the tolerance
  // (seeds 7-10: 0.060, 0.028, 0.061, 0.021 with the scene's rough-plastic ball as Mitsuba
  // shades it; 0.056 for seed 7 before); at 4000 0.025, 0.042, 0.048, 0.014.
  run.mpp = 4000;
  MltStatistics stats;
  const Image image = emlt_image(*scene, run, &stats);
  EXPECT_GT(stats_of(stats, "emlt-env").accepted, 10000u);
  expect_converged_to(image, reference, 2, 0.06, 0.04);
}

TEST(EmltUnbiased, FullMixAndPresetsConvergeOnTheSkyLitScene) {
  // Every path in the chains (direct light included), lit by the environment map only; the
  // mean of three seeds of 1,000 mutations per pixel each.
  EmltRun run;
  run.direct_separate = false;
  run.mpp = 3000;
  expect_mixes_converge("env-sky", {kEmltMix, "emlt-ani", "emlt-lin"}, run, 0.06, 0.04, 0.0, 3);
}

TEST(EmltInjectedBugs, GuidedLensBugsAreCaught) {
  // The linear lens perturbation with a wide stretch (α = 1, so that λ's ratio matters) and
  // the bidirectional mutation on the Cornell box, tile-wise against BDPT: 4 x 4 tiles of
  // 4 x 4 pixels. Measured: correct 0.015-0.020 (two seeds); selection probability ignored
  // 0.137, Υ re-chosen for the proposed path 0.075, reverse density dropped 0.107.
  const auto scene = shipped_scene("cornell-box", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  const auto deviation = [&](ensemble::InjectedBugs bugs) {
    EmltRun run;
    run.mix = with_bidir(std::make_unique<GuidedLensPerturbation>(bugs), 8.0);
    run.mpp = 3000;
    run.alpha = 1.0;
    run.neighbours = 32;  // Υ re-chosen for y matters more with more guides (M = 8: 0.054)
    return tile_deviation(emlt_image(*scene, run), reference, 4);
  };
  EXPECT_LT(deviation({}), 0.04);
  ensemble::InjectedBugs selection, upsilon, reverse;
  selection.ignore_selection = true;
  upsilon.upsilon_from_proposal = true;
  reverse.drop_reverse_density = true;
  EXPECT_GT(deviation(selection), 0.055) << "selection probability ignored";
  EXPECT_GT(deviation(upsilon), 0.055) << "Υ chosen for the proposed path";
  EXPECT_GT(deviation(reverse), 0.055) << "reverse density dropped";
}

// The nearby Υ moves with the path, so the reverse move must be evaluated against the
// proposal's own Υ (ensemble_guides.h): the guided lens perturbation evaluated against x's Υ
// instead is biased. The same setting as above, with the adaptive α and M = 8. Measured:
// correct 0.023, reverse against x's Υ 0.067.
TEST(EmltInjectedBugs, NearbyGuidesReverseAgainstTheCurrentGuidesIsCaught) {
  const auto scene = shipped_scene("cornell-box", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  const auto deviation = [&](ensemble::InjectedBugs bugs) {
    EmltRun run;
    run.mix = with_bidir(std::make_unique<GuidedLensPerturbation>(bugs), 8.0);
    run.mpp = 10000;
    run.nearby = true;
    const double d = tile_deviation(emlt_image(*scene, run), reference, 4);
    std::printf("[ info     ] nearby guides, lens: tile deviation %.4f\n", d);
    return d;
  };
  ensemble::InjectedBugs forward_guides;
  forward_guides.reverse_upsilon_of_x = true;
  EXPECT_LT(deviation({}), 0.04);
  EXPECT_GT(deviation(forward_guides), 0.055) << "reverse against x's Υ";
}

// The anisotropic path perturbation alone (with the bidirectional mutation) on the Cornell
// box's L D D E paths: maximum depth 3 with the direct light rendered separately leaves the
// chains nothing else, so x_c is always the emitter vertex; each order of the move runs on
// its own. 4 x 4 tiles of 4 x 4 pixels against BDPT at the same depth.
double two_bounce_anisotropic_deviation(double toward_camera_probability, double mpp,
                                        ensemble::InjectedBugs bugs = {},
                                        AnisotropicPathParams params = {}) {
  const auto scene = shipped_scene("cornell-box", 16);
  static const Image reference = [&] {
    RenderSettings s = test::base_settings();
    s.max_depth = 3;
    s.spp = 8192;
    return test::render(BidirectionalPathTracer(), *scene, s);
  }();
  params.toward_camera_probability = toward_camera_probability;
  EmltRun run;
  run.mix = with_bidir(std::make_unique<AnisotropicPathPerturbation>(params, bugs), 4.0);
  run.mpp = mpp;
  run.max_depth = 3;
  const double deviation = tile_deviation(emlt_image(*scene, run), reference, 4);
  std::printf("[ info     ] anisotropic path, toward %.1f: tile deviation %.4f\n",
              toward_camera_probability, deviation);
  return deviation;
}

TEST(EmltUnbiased, AnisotropicPathConvergesOnTwoBouncePaths) {
  // Both orders at random, as in the integrator. Measured 0.008-0.014 with either order alone
  // at 20000-40000 mutations per pixel; the bidirectional mutation alone gives 0.007.
  EXPECT_LT(two_bounce_anisotropic_deviation(0.5, 20000), 0.022);
}

TEST(EmltInjectedBugs, AnisotropicPathBugsAreCaught) {
  // Measured: degenerate casts kept (the state before they were refused) 0.045 from the
  // camera with the isotropic-Gaussian fallback option, where every cast goes through a plane
  // (0.034 with the default vMF fallback, 0.034 toward the camera, 0.028 with both orders
  // mixed; correct kernels 0.004-0.014); reverse density dropped 0.052 and 0.237 (at 5000 mpp). Σ
  // not refitted changes the image by only 0.025 here (the fitted part of Σ is small next to its
  // floor at this size); the kernel tests catch it (ensemble_kernel_test.cpp).
  ensemble::InjectedBugs degenerate, reverse;
  degenerate.keep_degenerate_casts = true;
  reverse.drop_reverse_density = true;
  AnisotropicPathParams plane_fallback;  // degenerate casts come from the plane Gaussians
  plane_fallback.fallback_concentration = 0.0;
  EXPECT_GT(two_bounce_anisotropic_deviation(0.0, 20000, degenerate, plane_fallback), 0.03)
      << "degenerate casts kept";
  EXPECT_GT(two_bounce_anisotropic_deviation(0.0, 5000, reverse), 0.04)
      << "reverse dropped, from the camera";
  EXPECT_GT(two_bounce_anisotropic_deviation(1.0, 5000, reverse), 0.04)
      << "reverse dropped, toward it";
}

TEST(EmltDeterminism, SameBitsOnOneAndTwoThreads) {
  const auto scene = shipped_scene("cornell-box", 8);
  EmltRun run;
  run.mpp = 300;
  run.ensemble_size = 32;
  run.threads = 1;
  const Image one = emlt_image(*scene, run);
  run.threads = 2;
  const Image two = emlt_image(*scene, run);
  run.seed = 8;
  const Image other = emlt_image(*scene, run);
  EXPECT_EQ(0, std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Rgb)));
  EXPECT_NE(0,
            std::memcmp(one.pixels.data(), other.pixels.data(), one.pixels.size() * sizeof(Rgb)));
}

TEST(EmltDriver, SwapsAndFallbacksAreCounted) {
  const auto scene = shipped_scene("cornell-box", 8);
  // One path per ensemble: Υ never holds two guides, so every guided step falls back to
  // Veach's perturbation; 64 pixels / (1 + 1) = 32 steps per path between swaps.
  EmltRun run;
  run.mpp = 64;
  run.ensemble_size = 1;
  MltStatistics stats;
  emlt_image(*scene, run, &stats);
  EXPECT_EQ(stats.ensemble_iterations, 32u);
  EXPECT_EQ(stats.swaps, 64u * 64u / 32u);
  const StrategyStats& lens = stats_of(stats, "emlt-lens");
  EXPECT_GT(lens.proposed, 0u);
  EXPECT_EQ(lens.fallbacks, lens.proposed - lens.failed);
  // With a real ensemble, guided steps are the rule.
  run.ensemble_size = 64;
  emlt_image(*scene, run, &stats);
  EXPECT_LT(stats_of(stats, "emlt-lens").fallbacks, stats_of(stats, "emlt-lens").proposed / 10);
}

}  // namespace
}  // namespace emlt
