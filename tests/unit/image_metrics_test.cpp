#include "emlt/image/image_metrics.h"

#include <gtest/gtest.h>

#include "emlt/core/error.h"

using namespace emlt;

namespace {
// 2x2 reference and image with hand-computable differences.
Image reference() {
  Image r(2, 2);
  r.at(0, 0) = Rgb(1.0f);
  r.at(1, 0) = Rgb(0.0f);
  r.at(0, 1) = Rgb(2.0f, 0.0f, 0.0f);
  r.at(1, 1) = Rgb(0.5f);
  return r;
}
Image image() {
  Image i(2, 2);
  i.at(0, 0) = Rgb(1.0f);                 // exact
  i.at(1, 0) = Rgb(0.1f);                 // d = 0.1 on every channel
  i.at(0, 1) = Rgb(1.0f, 0.0f, 0.0f);     // d = -1 on red only
  i.at(1, 1) = Rgb(0.5f, 0.5f, 1.0f);     // d = 0.5 on blue only
  return i;
}
}  // namespace

TEST(ImageMetrics, MatchHandComputedValues) {
  const ImageMetrics m = compare_images(reference(), image());
  // Per-pixel channel-mean squared errors: 0, 0.01, 1/3, 0.25/3.
  const double mse = (0.0 + 0.01 + 1.0 / 3.0 + 0.25 / 3.0) / 4.0;
  EXPECT_NEAR(m.mse, mse, 1e-7);
  // relMSE: pixel (1,0): 0.01/0.01 = 1 per channel; (0,1): 1/(4+0.01)/3; (1,1): 0.25/(0.25+0.01)/3.
  const double rel = (0.0 + 1.0 + (1.0 / 4.01) / 3.0 + (0.25 / 0.26) / 3.0) / 4.0;
  EXPECT_NEAR(m.rel_mse, rel, 1e-6);
  // Means: reference sum = 3 + 0 + 2 + 1.5 = 6.5; image sum = 3 + 0.3 + 1 + 2 = 6.3.
  EXPECT_NEAR(m.mean_ratio, 6.3 / 6.5, 1e-6);
  EXPECT_TRUE(std::isnan(m.mse_no_emitter));
  EXPECT_EQ(m.pixels, 4u);
}

TEST(ImageMetrics, CropAndEmitterMaskRestrictThePixels) {
  const ImageMetrics crop = compare_images(reference(), image(), PixelRegion{1, 0, 1, 2});
  EXPECT_NEAR(crop.mse, (0.01 + 0.25 / 3.0) / 2.0, 1e-7);
  const std::vector<uint8_t> sees = {0, 1, 1, 0};  // pixels (1,0) and (0,1) see an emitter
  const ImageMetrics masked = compare_images(reference(), image(), std::nullopt, &sees);
  EXPECT_NEAR(masked.mse_no_emitter, (0.0 + 0.25 / 3.0) / 2.0, 1e-7);
  EXPECT_EQ(masked.pixels_no_emitter, 2u);
}

TEST(ImageMetrics, RejectsMismatchedSizesAndBadCrops) {
  EXPECT_THROW(compare_images(reference(), Image(3, 2)), Error);
  EXPECT_THROW(compare_images(reference(), image(), PixelRegion{1, 1, 2, 2}), Error);
  EXPECT_THROW(parse_pixel_region("1,2,3"), Error);
  const PixelRegion r = parse_pixel_region("4,5,6,7");
  EXPECT_EQ(r.x + r.y + r.width + r.height, 22);
}

TEST(ImageMetrics, ErrorMapIsBrighterWhereTheErrorIsLarger) {
  const Image map = relative_error_map(reference(), image());
  EXPECT_LT(luminance(map.at(0, 0)), luminance(map.at(0, 1)));
  EXPECT_LT(luminance(map.at(0, 1)), luminance(map.at(1, 0)));
}
