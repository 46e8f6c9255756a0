// Inputs the fuzz targets (tests/fuzz/, scripts/fuzz.sh) found, each kept in the target's
// corpus as tests/fuzz/corpus/TARGET/regression-*: every one must now be refused with an
// emlt::Error (never a hang or a crash). A reader runs in a forked child under an alarm,
// so an input that makes it loop forever fails the test instead of stalling the suite.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include "emlt/core/error.h"
#include "emlt/render/image.h"

using namespace emlt;
namespace fs = std::filesystem;

namespace {

fs::path regression_input(const std::string& target, const std::string& name) {
  return fs::path(EMLT_SOURCE_DIR) / "tests/fuzz/corpus" / target / name;
}

// Exits 0 when `read` throws emlt::Error within 20 s, 1 when it returns, and dies of
// SIGALRM when it hangs.
void refused_in_time(const std::function<void()>& read) {
  alarm(20);
  try {
    read();
  } catch (const Error&) {
    std::_Exit(0);
  }
  std::_Exit(1);
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
