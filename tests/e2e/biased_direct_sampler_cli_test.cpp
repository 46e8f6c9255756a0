// The direct-lighting options only `direct` can honour, from the command line: the biased
// estimators (--direct-sampler bmc and adaptive), which the integrators whose direct light must
// be unbiased refuse in one line, and cube-balanced's fractional face counts, which need
// several light samples per point; their own options are range-checked.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/cli_checks.h"
#include "support/test_support.h"

using namespace emlt;
using test::cornell;
using test::emlt_cmd;
using test::expect_clean_failure;
namespace fs = std::filesystem;

// Adaptive sampling is biased (its cells follow the values it finds): the integrators
// whose direct light must be unbiased refuse it with one line; `direct` renders with it.
TEST(Cli, AdaptiveDirectSamplerOnlyWhereABiasedDirectEstimateIsAllowed) {
  const fs::path dir = test::scratch_dir("adaptive-direct");
  for (const char* integrator : {"pt", "mlt"}) {
    const fs::path out = dir / (std::string(integrator) + ".exr");
    expect_clean_failure("render " + cornell() + " --integrator " + integrator +
                             " --direct-sampler adaptive --spp 1 --width 8 --height 8 -o " +
                             out.string(),
                         "--direct-sampler adaptive is a biased", out);
  }
  std::string text;
  EXPECT_EQ(test::run_command(emlt_cmd("render " + cornell() +
                                       " --integrator direct --direct-sampler adaptive "
                                       "--direct-samples 4 --spp 1 --width 8 --height 8 --quiet -o " +
                                       (dir / "direct.exr").string()),
                              &text),
            0)
      << text;
  EXPECT_TRUE(fs::exists(dir / "direct.exr"));
}

// Bayesian Monte Carlo's estimate is biased (its weights are fixed by the prior): integrators
// that need an unbiased direct-lighting estimate refuse it in one line; `direct` takes it.
TEST(CliBadInput, BiasedBmcDirectSamplerOnlyForDirect) {
  const fs::path dir = test::scratch_dir("bmc-refused");
  const std::string base = "render " + cornell() + " --width 8 --height 8 --spp 1 --quiet -o " +
                           (dir / "o.exr").string() + " --direct-sampler bmc ";
  expect_clean_failure(base + "--integrator pt", "--direct-sampler bmc is biased", dir / "o.exr");
  expect_clean_failure(base + "--integrator mlt --direct separate --mpp 1",
                       "mlt needs an unbiased direct-lighting estimate", dir / "o.exr");
  expect_clean_failure(base + "--integrator direct --bmc-noise 0", "--bmc-noise", dir / "o.exr");
  expect_clean_failure(base + "--integrator direct --direct-samples 2048", "up to 1024",
                       dir / "o.exr");
  std::string text;
  EXPECT_EQ(test::run_command(emlt_cmd(base + "--integrator direct --direct-samples 4"), &text), 0)
      << text;
  EXPECT_TRUE(fs::exists(dir / "o.exr"));
}

// Fractional face counts share several light samples among the faces; the path tracer and
// the chains' direct pass draw one light sample per vertex, so asking them for it is refused.
TEST(CliBadInput, FractionalFaceCountsOnlyForDirect) {
  const fs::path dir = test::scratch_dir("face-counts");
  const std::string base = "render " + cornell() + " --width 8 --height 8 --spp 1 --quiet -o " +
                           (dir / "o.exr").string() + " --env-sampler cube-balanced ";
  expect_clean_failure(base + "--integrator pt --env-face-counts fractional",
                       "--env-face-counts fractional needs several light samples", dir / "o.exr");
  expect_clean_failure(base + "--integrator direct --env-face-counts halves", "--env-face-counts",
                       dir / "o.exr");
  std::string text;
  EXPECT_EQ(test::run_command(emlt_cmd(base + "--integrator pt --env-face-counts sampled"), &text),
            0)
      << text;
  EXPECT_EQ(
      test::run_command(emlt_cmd(base + "--integrator direct --env-face-counts fractional"), &text),
      0)
      << text;
  EXPECT_TRUE(fs::exists(dir / "o.exr"));
}
