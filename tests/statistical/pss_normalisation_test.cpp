// pssmlt's and mmlt's b that converges with the render (pss_chains.h, pss_normalisation.h):
// the chains' part of the image is scaled by the mean f* of every large step, so an image
// whose bootstrap's b is off still converges to BDPT's, where the old scaling by the
// bootstrap's b (injected: PssOptions::scale_by_bootstrap_b) keeps the bootstrap's error in
// every pixel however long the chains run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/pss/pss_integrator.h"
#include "support/mlt_test_helpers.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

double mean_luminance(const Image& image) {
  double sum = 0.0;
  for (const Rgb& p : image.pixels) sum += double(luminance(p));
  return sum / double(image.pixels.size());
}

// BDPT's mean luminance over `runs` seeds of `spp` each, and its standard error from their
// spread.
struct Reference {
  double mean = 0.0, error = 0.0;
};
Reference bdpt_mean(const Scene& scene, int max_depth, int runs, int spp) {
  std::vector<double> means;
  for (int r = 0; r < runs; ++r) {
    RenderSettings s;
    s.max_depth = max_depth;
    s.spp = spp;
    s.threads = 2;
    s.seed = 1000 + uint64_t(r);
    means.push_back(mean_luminance(test::render(BidirectionalPathTracer(), scene, s)));
  }
  Reference ref;
  for (const double m : means) ref.mean += m / runs;
  for (const double m : means) ref.error += (m - ref.mean) * (m - ref.mean);
  ref.error = std::sqrt(ref.error / (runs - 1) / runs);
  return ref;
}

struct PssRun {
  double mean = 0.0;  // the image's mean luminance
  MltStatistics stats;
};
PssRun render_pss(const Scene& scene, RenderSettings s, PssOptions options) {
  s.progress = false;
  ProgressReporter quiet(false);
  PssMltIntegrator integrator(options);
  PssRun run;
  run.mean = mean_luminance(integrator.render(scene, s, quiet).image);
  run.stats = integrator.statistics();
  return run;
}

// z of an image's mean against BDPT's: its distance over b's printed error carried to the
// image (b's relative error times the mean: the chains' part, scaled by b, is most of it)
// and the reference's own.
double z_of(const PssRun& run, const Reference& ref) {
  const double relative = run.stats.b_standard_error / run.stats.b;
  return (run.mean - ref.mean) / std::hypot(relative * run.mean, ref.error);
}

}  // namespace

// The caustic pool (normalisation_pass_test.cpp): light reaches much of the floor only by
// rare, bright specular paths, which a bootstrap of 2,048 samples mostly misses, so its b is
// 5-12 % too small while its printed error says 2 %. pssmlt (over the path tracer, paths of
// up to 8 segments, 16 x 16, 4,096 mutations per pixel: 315,000 large steps behind b): the
// images' mean z^2 over 8 seeds against BDPT is 0.11 with the converging b, 2.30 scaled by
// the bootstrap's, every seed 2-4 % darker than BDPT. Deterministic (fixed seeds).
//
// mmlt is left out here: at this budget most seeds' b_k, pooled from large steps and BDPT
// samples, have not met the rarest paths, which no BDPT connection forms; at four times the
// budget they have (DISABLED_MmltOnTheCausticPool below, docs/normalisation.md).
TEST(PssNormalisation, PssmltMatchesBdptWhereTheBootstrapMissesTheCaustics) {
  const auto scene = test::shipped_scene("caustic-pool", 16);
  const Reference ref = bdpt_mean(*scene, 8, 4, 1024);
  RenderSettings s;
  s.max_depth = 8;
  s.bootstrap_samples = 2048;
  s.mutations_per_pixel = 4096;
  s.direct_spp = 1024;
  s.threads = 2;
  const int seeds = 8;
  for (const bool injected : {false, true}) {
    PssOptions options;
    options.scale_by_bootstrap_b = injected;
    double z2 = 0.0;
    int darker = 0;
    for (int seed = 1; seed <= seeds; ++seed) {
      s.seed = uint64_t(seed);
      const PssRun run = render_pss(*scene, s, options);
      const double z = z_of(run, ref);
      z2 += z * z / seeds;
      darker += run.mean < ref.mean;
      std::printf(
          "[ info     ] %s seed %d: image / BDPT %.4f, b %.6f +- %.2g (bootstrap %.6f), z %+.2f\n",
          injected ? "bootstrap's b" : "converging b", seed, run.mean / ref.mean, run.stats.b,
          run.stats.b_standard_error, run.stats.bootstrap_b, z);
    }
    std::printf("[ info     ] %s: mean z^2 %.2f, %d of %d seeds darker than BDPT %.6f +- %.2g\n",
                injected ? "bootstrap's b" : "converging b", z2, darker, seeds, ref.mean,
                ref.error);
    if (injected) {
      EXPECT_GT(z2, 1.5);
      EXPECT_EQ(darker, seeds);
    } else {
      EXPECT_LT(z2, 1.0);
    }
  }
}

// mmlt's b_k pools its large steps with BDPT samples split by length (the path-space
// bootstrap's, then those drawn beside the chains, pss_chains.h): each BDPT sample adds to
// every length, with all of its k + 1 strategies, where a large step adds one strategy's
// sample to one length. On the Cornell box (16 x 16, paths of up to 6 segments, a bootstrap
// of 20,000, 1,024 mutations per pixel) b's printed error is 0.52 % pooled against 0.83 % from
// the large steps alone (injected: PssOptions::mmlt_b_from_large_steps_only), and the image
// stays within 2 % and 3 printed errors of BDPT's. (A BDPT sample's weights counted one length
// too long, injected in the split, moves this image by only 1.8 %: the split's own test,
// NormalisationPass.SplitByLengthSumsEachLengthOfTheSameSamples, is the one that catches it.)
TEST(PssNormalisation, MmltPoolsBdptSamplesSplitByLength) {
  const auto scene = test::shipped_scene("cornell-box", 16);
  const Reference ref = bdpt_mean(*scene, 6, 4, 256);
  RenderSettings s;
  s.max_depth = 6;
  s.bootstrap_samples = 20000;
  s.mutations_per_pixel = 1024;
  s.direct_spp = 256;
  s.threads = 2;
  s.seed = 3;
  double relative[2] = {0.0, 0.0};
  for (const bool injected : {false, true}) {
    PssOptions options;
    options.multiplexed = true;
    options.mmlt_b_from_large_steps_only = injected;
    const PssRun run = render_pss(*scene, s, options);
    const double z = z_of(run, ref);
    relative[injected] = run.stats.b_standard_error / run.stats.b;
    std::printf("[ info     ] %s: image / BDPT %.4f, b %.6f +- %.2g (%llu BDPT samples), z %+.2f\n",
                injected ? "large steps" : "pooled", run.mean / ref.mean, run.stats.b,
                run.stats.b_standard_error,
                static_cast<unsigned long long>(run.stats.b_bidirectional_samples), z);
    EXPECT_NEAR(run.mean / ref.mean, 1.0, 0.02);
    EXPECT_LT(std::abs(z), 3.0);
    EXPECT_EQ(run.stats.b_bidirectional_samples > 0, !injected);
  }
  EXPECT_LT(relative[0], 0.75 * relative[1]);
}

// The caustic pool, where light reaches much of the floor only by paths that no BDPT
// connection forms (specular on both sides of the floor's vertex), found only by rare camera
// paths through the water to the small light. docs/normalisation.md's figures (8 seeds, a
// bootstrap of 2,048, paths of up to 8 segments; about 40 s a budget on two cores, so not in
// the default run; MMLT_MPP sets the budget, default 16,384):
//   emlt_statistical_tests --gtest_also_run_disabled_tests
//     --gtest_filter=PssNormalisation.DISABLED_MmltOnTheCausticPool
TEST(PssNormalisation, DISABLED_MmltOnTheCausticPool) {
  const auto scene = test::shipped_scene("caustic-pool", 16);
  const Reference ref = bdpt_mean(*scene, 8, 4, 1024);
  RenderSettings s;
  s.max_depth = 8;
  s.bootstrap_samples = 2048;
  const char* mpp = std::getenv("MMLT_MPP");
  s.mutations_per_pixel = mpp ? std::atof(mpp) : 16384.0;
  s.direct_spp = 1024;
  s.threads = 2;
  const int seeds = 8;
  for (const bool large_steps_only : {false, true}) {
    PssOptions options;
    options.multiplexed = true;
    options.mmlt_b_from_large_steps_only = large_steps_only;
    double z2 = 0.0, spread = 0.0;
    for (int seed = 1; seed <= seeds; ++seed) {
      s.seed = uint64_t(seed);
      const PssRun run = render_pss(*scene, s, options);
      const double z = z_of(run, ref);
      z2 += z * z / seeds;
      spread += (run.mean / ref.mean - 1.0) * (run.mean / ref.mean - 1.0) / seeds;
      std::printf(
          "[ info     ] %s seed %d: image / BDPT %.4f, b %.6f +- %.2g (%llu BDPT samples), "
          "z %+.2f, %.2f s of %.2f s beside the chains\n",
          large_steps_only ? "large steps" : "pooled", seed, run.mean / ref.mean, run.stats.b,
          run.stats.b_standard_error,
          static_cast<unsigned long long>(run.stats.b_bidirectional_samples), z,
          run.stats.normalisation_seconds, run.stats.seconds);
    }
    std::printf("[ info     ] %s: mean z^2 %.2f, rms of image / BDPT - 1 %.4f\n",
                large_steps_only ? "large steps" : "pooled", z2, std::sqrt(spread));
    EXPECT_LT(z2, 1.5);
  }
}

// With the bootstrap's b forced to half or twice its value (PssOptions::bootstrap_b_factor),
// as a bootstrap that far off would give, the weights' b is wrong by 2x, yet the images of
// pssmlt and mmlt stay BDPT's, to 0.1 % of the image with the bootstrap's own b: the weights'
// b only chooses how the two halves of Kelemen's estimator share each path. Scaled by the
// bootstrap's b, the chains' half comes out half or twice as bright (the image 11 % darker,
// 15-17 % brighter). The Cornell box at 16 x 16, paths of up to 6 segments, 1,024 mutations
// per pixel; the margins: the image's own noise (about 1 %) and b's printed error (0.6-0.8 %).
TEST(PssNormalisation, ImageDoesNotDependOnTheWeightsB) {
  const auto scene = test::shipped_scene("cornell-box", 16);
  const Reference ref = bdpt_mean(*scene, 6, 4, 256);
  for (const bool multiplexed : {false, true})
    for (const double factor : {0.5, 2.0})
      for (const bool injected : {false, true}) {
        RenderSettings s;
        s.max_depth = 6;
        s.bootstrap_samples = 20000;
        s.mutations_per_pixel = 1024;
        s.direct_spp = 256;
        s.threads = 2;
        s.seed = 3;
        PssOptions options;
        options.multiplexed = multiplexed;
        options.bootstrap_b_factor = factor;
        options.scale_by_bootstrap_b = injected;
        const PssRun run = render_pss(*scene, s, options);
        const double z = z_of(run, ref);
        std::printf(
            "[ info     ] %s, weights' b x %.1f, %s: image / BDPT %.4f, b %.6f +- %.2g, z %+.2f\n",
            multiplexed ? "mmlt" : "pssmlt", factor, injected ? "bootstrap's b" : "converging b",
            run.mean / ref.mean, run.stats.b, run.stats.b_standard_error, z);
        if (injected) {
          EXPECT_GT(std::abs(run.mean / ref.mean - 1.0), 0.08);
          EXPECT_GT(std::abs(z), 5.0);
        } else {
          EXPECT_NEAR(run.mean / ref.mean, 1.0, 0.02);
          EXPECT_LT(std::abs(z), 3.0);
        }
      }
}
