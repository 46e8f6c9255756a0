// Mitsuba 0.6's box filter reads a `radius` (0.5 by default): a sample counts fully for every
// pixel whose centre lies within the radius of it on each axis. The loader reads it (verdict
// exact) and the film's filter spreads a sample over exactly those pixels, equally.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "emlt/film/pixel_filter.h"
#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

SceneDescription load_with_filter(const std::string& name, const std::string& rfilter) {
  const std::string xml = R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
      )" + rfilter + R"(</film>
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>
)";
  return load_scene_description(test::write_file(test::scratch_dir("box-radius"), name, xml));
}

}  // namespace

TEST(MitsubaBoxFilterRadius, LoaderReadsTheRadius) {
  const SceneDescription plain = load_with_filter("plain.xml", R"(<rfilter type="box"/>)");
  EXPECT_EQ(plain.verdict(), "exact");
  EXPECT_EQ(plain.camera.filter.kind, PixelFilterDesc::Kind::Box);
  EXPECT_FLOAT_EQ(plain.camera.filter.box_radius, 0.5f);
  EXPECT_TRUE(PixelFilter(plain.camera.filter, 8, 8).is_box());

  const SceneDescription wide = load_with_filter(
      "wide.xml", R"(<rfilter type="box"><float name="radius" value="1"/></rfilter>)");
  EXPECT_EQ(wide.verdict(), "exact");
  EXPECT_FLOAT_EQ(wide.camera.filter.box_radius, 1.0f);
}

TEST(MitsubaBoxFilterRadius, SampleCountsEquallyForEveryPixelWithinTheRadius) {
  PixelFilterDesc desc;
  desc.box_radius = 1.0f;
  const PixelFilter filter(desc, 8, 8);
  EXPECT_FALSE(filter.is_box());
  // Pixel centres at x 2.5 (1.2 away), 3.5 (0.2), 4.5 (0.8); y 2.5 (1.1), 3.5 (0.1), 4.5 (0.9).
  std::map<uint32_t, float> weights;
  filter.splat(Vec2(3.7f, 3.6f), [&](uint32_t pixel, float w) { weights[pixel] += w; });
  ASSERT_EQ(weights.size(), 4u);
  for (const uint32_t pixel : {3u * 8u + 3u, 3u * 8u + 4u, 4u * 8u + 3u, 4u * 8u + 4u}) {
    ASSERT_EQ(weights.count(pixel), 1u) << pixel;
    // Each interior footprint covers 2 x 2 pixels of area: weight 1/4 per sample density.
    EXPECT_NEAR(weights[pixel], 0.25f, 1e-5f) << pixel;
  }
  // The one-pixel box would have put it in pixel (3, 3) alone.
  std::map<uint32_t, float> narrow;
  PixelFilter(PixelFilterDesc{}, 8, 8).splat(Vec2(3.7f, 3.6f), [&](uint32_t pixel, float w) {
    narrow[pixel] += w;
  });
  ASSERT_EQ(narrow.size(), 1u);
  EXPECT_EQ(narrow.begin()->first, 3u * 8u + 3u);
}
