// Mitsuba 0.6's envmap reads a `gamma` that replaces the map's own curve, as a bitmap
// texture's does: -1 the sRGB curve, g > 0 the curve v^g, 0 (the default) the file's; a
// float map's values are bent by it too. The loader reads it (verdict exact) and refuses a
// value that is no curve.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

std::string scene_with_gamma(const std::string& gamma) {
  return R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
  <emitter type="envmap"><string name="filename" value=")" +
         test::source_path("tests/conformance/scenes/assets/sky.exr") + "\"/>" + gamma +
         R"(</emitter>
  <shape type="sphere"/>
</scene>
)";
}

std::string write(const std::string& name, const std::string& gamma) {
  return test::write_file(test::scratch_dir("envmap-gamma"), name, scene_with_gamma(gamma));
}

}  // namespace

TEST(MitsubaEnvmapGamma, GammaBendsTheMapsValues) {
  const SceneDescription plain = load_scene_description(write("plain.xml", ""));
  const SceneDescription bent =
      load_scene_description(write("bent.xml", R"(<float name="gamma" value="2.2"/>)"));
  EXPECT_EQ(bent.verdict(), "exact");
  const Image& a = plain.environment.map;
  const Image& b = bent.environment.map;
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  ASSERT_FALSE(a.pixels.empty());
  bool differs = false;
  for (size_t i = 0; i < a.pixels.size(); i += 97) {
    for (int k = 0; k < 3; ++k) {
      const float expected = std::pow(a.pixels[i][k], 2.2f);
      EXPECT_NEAR(b.pixels[i][k], expected, 1e-5f * (1.0f + expected)) << i;
      differs |= std::abs(a.pixels[i][k] - expected) > 1e-3f;
    }
  }
  EXPECT_TRUE(differs);  // the map is not all zeros and ones

  EXPECT_EQ(
      load_scene_description(write("srgb.xml", R"(<float name="gamma" value="-1"/>)")).verdict(),
      "exact");
  const std::string bad = write("bad.xml", R"(<float name="gamma" value="-2"/>)");
  EXPECT_NE(
      test::error_of([&] { load_scene_description(bad); }).find("envmap gamma -2 is not a curve"),
      std::string::npos);
}
