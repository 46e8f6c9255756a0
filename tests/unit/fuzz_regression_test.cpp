// Inputs the fuzz targets (tests/fuzz/, scripts/fuzz.sh) found, each kept in the target's
// corpus as tests/fuzz/corpus/TARGET/regression-*: every one must now be refused with an
// emlt::Error, or for a checkpoint's state an emlt::StateError (never a hang or a crash).
// A reader runs in a forked child under an alarm, so an input that makes it loop forever
// fails the test instead of stalling the suite. Sanitizer reports among the findings (an
// out-of-range conversion, a null pointer given to memcpy) show as failures in the
// sanitizer build (scripts/check_sanitizers.sh).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>

#include "emlt/core/error.h"
#include "emlt/core/state_io.h"
#include "emlt/image/image.h"
#include "emlt/integrators/registry.h"
#include "emlt/run/checkpoint_file.h"
#include "fuzz/checkpoint_resume.h"
#include "support/test_support.h"

using namespace emlt;
namespace fs = std::filesystem;

namespace {

fs::path regression_input(const std::string& target, const std::string& name) {
  return fs::path(EMLT_SOURCE_DIR) / "tests/fuzz/corpus" / target / name;
}

// Exits 0 when `read` throws emlt::Error (or StateError) within 20 s, 1 when it returns,
// and dies of SIGALRM when it hangs.
void refused_in_time(const std::function<void()>& read) {
  alarm(20);
  try {
    read();
  } catch (const Error&) {
    std::_Exit(0);
  } catch (const StateError&) {
    std::_Exit(0);
  }
  std::_Exit(1);
}

// Exits 0 when `run` returns within 20 s, 1 when it throws, and dies of SIGALRM when it
// hangs (or of the sanitizer's report, in the sanitizer build).
void finishes_in_time(const std::function<void()>& run) {
  alarm(20);
  try {
    run();
  } catch (const std::exception&) {
    std::_Exit(1);
  }
  std::_Exit(0);
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// An input of the checkpoint target whose first byte picks an integrator (modes 1 .. 8 of
// tests/fuzz/fuzz_checkpoint.cpp): that integrator's render resumed from the rest.
void resume_checkpoint_input(const fs::path& path) {
  const std::string bytes = read_bytes(path);
  const unsigned mode =
      bytes.empty() ? 0 : uint8_t(bytes[0]) % (fuzz::kCheckpointIntegrators.size() + 1);
  if (mode == 0) throw std::runtime_error(path.string() + ": not an integrator state");
  fuzz::CheckpointFixture::get().resume(fuzz::kCheckpointIntegrators[mode - 1], bytes.substr(1));
}

}  // namespace

// stb's Radiance decoder looped forever on a run-length scanline with a zero count.
TEST(FuzzRegressionDeathTest, RadianceHdrZeroRunLengthCountIsRefused) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const std::string path = regression_input("image_hdr", "regression-zero-rle-count.hdr");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { read_image(path); }), ::testing::ExitedWithCode(0), "");
}

// A run-length scanline that ends early was decoded from zeros past the end of the file.
TEST(FuzzRegressionDeathTest, RadianceHdrTruncatedRunLengthDataIsRefused) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const std::string path = regression_input("image_hdr", "regression-truncated-rle.hdr");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { read_image(path); }), ::testing::ExitedWithCode(0), "");
}

// The same hang behind a header line starting with a NUL byte, which ends stb's header.
TEST(FuzzRegressionDeathTest, RadianceHdrHeaderEndingInNulLineIsChecked) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const std::string path = regression_input("image_hdr", "regression-nul-header-line.hdr");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { read_image(path); }), ::testing::ExitedWithCode(0), "");
}

// 24 bytes named .png that stb decoded as a headerless TGA of 18505 x 21060 texels (zeros
// past the end): 4.7 GB allocated for an image that is not there.
TEST(FuzzRegressionDeathTest, PngThatIsNotAPngIsRefused) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const std::string path = regression_input("image_png", "regression-tga-in-png.png");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { read_image(path); }), ::testing::ExitedWithCode(0), "");
}

// A 525-byte JPEG header claiming 65032 x 2049 texels, decoded from zeros (seconds and
// 1.6 GB for nothing): every 8 x 8 block needs at least one bit of data.
TEST(FuzzRegressionDeathTest, JpegTooShortForItsSizeIsRefused) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const std::string path = regression_input("image_jpg", "regression-huge-empty-jpeg.jpg");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { read_image(path); }), ::testing::ExitedWithCode(0), "");
}

// 647 bytes holding a Huffman table that defines no valid code. stb's JPEG decoder built
// it anyway and, in the fuzzer after other inputs (it depends on what the heap held; alone
// stb refuses it), failed an assert while decoding with it: an abort, as Debian builds stb
// with asserts on. JPEG now goes to libjpeg: "Bogus Huffman table definition".
TEST(FuzzRegressionDeathTest, JpegWithABadHuffmanCodeIsRefused) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const std::string path = regression_input("image_jpg", "regression-stb-huffman-assert.jpg");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { read_image(path); }), ::testing::ExitedWithCode(0), "");
}

// Checkpoints (fuzz_checkpoint): the seeds are real checkpoints of the target's render, and
// the loaders' checks must let every one of them through. A seed refused here means either a
// check too strict for real states or a state format changed since the corpus was written
// (then run tests/fuzz/make_checkpoint_corpus.py, or the fuzzer starts from nothing).
TEST(FuzzRegressionTest, CheckpointSeedsResume) {
  const fs::path corpus = fs::path(EMLT_SOURCE_DIR) / "tests/fuzz/corpus/checkpoint";
  int seeds = 0;
  for (const auto& entry : fs::directory_iterator(corpus)) {
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    try {
      if (name.starts_with("state-")) {
        resume_checkpoint_input(entry.path());
      } else if (name.starts_with("file-")) {
        // A whole file after the mode byte; its integrator is the one in its name.
        const fs::path dir = test::scratch_dir("checkpoint");
        const std::string file =
            test::write_file(dir, "seed.ck", read_bytes(entry.path()).substr(1));
        const std::string integrator = name.substr(5, name.find('-', 5) - 5);
        fuzz::CheckpointFixture::get().resume(integrator, checkpoint_file::read(file).state);
      } else {
        continue;
      }
      ++seeds;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "refused: " << e.what();
    }
  }
  EXPECT_GE(seeds, 10);
}

// Every resumed BDPT render handed memcpy the null data() of its empty strategy sums (empty
// without --bdpt-strategies): undefined behaviour, reported by UBSan on any such state.
TEST(FuzzRegressionDeathTest, CheckpointBdptStateWithoutStrategyImagesResumes) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const fs::path dir = test::scratch_dir("bdpt");
  const auto& fixture = fuzz::CheckpointFixture::get();
  RenderSettings settings = fixture.settings("bdpt");
  RenderControl control((dir / "bdpt.ck").string(), 0.0, {});
  settings.control = &control;
  ProgressReporter progress(false);
  make_integrator("bdpt")->render(fixture.scene(), settings, progress);
  const std::string state = checkpoint_file::read((dir / "bdpt.ck").string()).state;
  EXPECT_EXIT(finishes_in_time([&] { fixture.resume("bdpt", state); }),
              ::testing::ExitedWithCode(0), "");
}

// A chain's path whose raster position lay far outside the image: the film index was
// converted from it to int, out of range (UBSan).
TEST(FuzzRegressionDeathTest, CheckpointPathLandingOutsideTheImageIsRefused) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const fs::path path = regression_input("checkpoint", "regression-path-lands-outside-image");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { resume_checkpoint_input(path); }),
              ::testing::ExitedWithCode(0), "");
}

// A chain with a negative contribution: its splats reached the fixed-point film, whose
// conversion to integers assumes non-negative values (UBSan: out of range for int64).
TEST(FuzzRegressionDeathTest, CheckpointNegativeChainContributionIsRefused) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const fs::path path = regression_input("checkpoint", "regression-negative-contribution");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { resume_checkpoint_input(path); }),
              ::testing::ExitedWithCode(0), "");
}

// A path vertex whose normal and shading tangent were 1e27 and 1e28 long (finite, so they
// passed): a mutation traced a ray built from them that Embree refuses, failing an
// assertion inside Embree (abort).
TEST(FuzzRegressionDeathTest, CheckpointPathVertexWithHugeNormalIsRefused) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const fs::path path = regression_input("checkpoint", "regression-path-vertex-huge-normal");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { resume_checkpoint_input(path); }),
              ::testing::ExitedWithCode(0), "");
}

// A sweep under way promising one chain 2^40 more steps (and the sweep as many), with the
// counts otherwise consistent: the render ran them all, never ending.
TEST(FuzzRegressionDeathTest, CheckpointSweepPromisingEndlessStepsIsRefused) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const fs::path path = regression_input("checkpoint", "regression-sweep-beyond-checkpoint");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { resume_checkpoint_input(path); }),
              ::testing::ExitedWithCode(0), "");
}

// A sweep under way starting at chain 2^64 - 1: first + count wrapped around to 0, passed
// the check against the chain count, and the render indexed the chains there.
TEST(FuzzRegressionDeathTest, CheckpointSweepStartingPastTheChainsIsRefused) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const fs::path path = regression_input("checkpoint", "regression-sweep-first-wraps-around");
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EXIT(refused_in_time([&] { resume_checkpoint_input(path); }),
              ::testing::ExitedWithCode(0), "");
}
