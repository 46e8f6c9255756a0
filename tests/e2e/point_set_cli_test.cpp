// The unbiased randomised point sets (--direct-sampler fibonacci, sobol,
// larcher-pillichshammer, blue-noise) from the command line: every integrator whose direct
// light must be unbiased takes them, as `direct` does; an unknown set is refused in one line
// that lists the choices.
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

TEST(Cli, UnbiasedPointSetsWhereverDirectLightIsSampled) {
  const fs::path dir = test::scratch_dir("point-sets");
  for (const char* set : {"sobol", "larcher-pillichshammer", "blue-noise"})
    for (const char* integrator : {"direct", "pt", "mlt --direct separate --mpp 1"}) {
      const fs::path out = dir / "o.exr";
      fs::remove(out);
      std::string text;
      EXPECT_EQ(test::run_command(emlt_cmd("render " + cornell() + " --integrator " + integrator +
                                           " --direct-sampler " + set +
                                           " --direct-samples 3 --spp 1 --width 8 --height 8 "
                                           "--quiet -o " +
                                           out.string()),
                                  &text),
                0)
          << set << " " << integrator << ": " << text;
      EXPECT_TRUE(fs::exists(out)) << set << " " << integrator;
    }
  expect_clean_failure("render " + cornell() +
                           " --direct-sampler sobel --spp 1 --width 8 --height 8 -o " +
                           (dir / "bad.exr").string(),
                       "sobol,larcher-pillichshammer,blue-noise", dir / "bad.exr");
}
