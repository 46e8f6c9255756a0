// Mitsuba 0.6's sky, sun and sunsky emitters: the lat-long maps the loader builds against
// texels Mitsuba's own plugins produced (tests/unit/data/mitsuba_sky_probes.json, measured
// by tools/sky/make_sky_probes.py), and the loader's checks and refusals.
#include "emlt/scene/sky.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

namespace emlt {
namespace {

SceneDescription load_emitters(const std::string& test, const std::string& emitters) {
  const auto dir = test::scratch_dir(test);
  return load_mitsuba_scene(
      test::write_file(dir, "scene.xml", "<scene version=\"0.6.0\">" + emitters + "</scene>"));
}

// Every probed texel of each case, to Mitsuba's storage precision: its envmap keeps half
// floats (a few 1e-4 relative), and a probe's direction, a float off the texel centre,
// leaks about 1e-6 of a neighbour into it (which matters only beside the sun).
TEST(MitsubaSky, MapsMatchTheTexelsMitsubaBuilds) {
  std::ifstream in(test::source_path("tests/unit/data/mitsuba_sky_probes.json"));
  ASSERT_TRUE(in) << "missing probe file";
  const nlohmann::json probes = nlohmann::json::parse(in);
  ASSERT_EQ(probes["cases"].size(), 4u);
  for (const auto& c : probes["cases"]) {
    const std::string name = c["name"];
    SCOPED_TRACE(name);
    const SceneDescription desc = load_emitters("sky_" + name, c["xml"].get<std::string>());
    ASSERT_EQ(desc.environment.kind, EnvironmentDesc::Kind::Map);
    const Image& map = desc.environment.map;
    ASSERT_EQ(map.width, c["width"].get<int>());
    ASSERT_EQ(map.height, c["height"].get<int>());
    EXPECT_TRUE(desc.divergences.empty()) << desc.divergences.front().message;
    double brightest = 0.0;
    for (const auto& p : c["probes"])
      for (double v : p["rgb"]) brightest = std::max(brightest, v);
    int compared = 0;
    for (const auto& p : c["probes"]) {
      const int x = p["x"], y = p["y"];
      for (int k = 0; k < 3; ++k) {
        const double expected = p["rgb"][k], got = map.at(x, y)[k];
        EXPECT_NEAR(got, expected, 2e-3 * std::abs(expected) + 1e-5 * brightest)
            << "texel (" << x << ", " << y << ") channel " << k;
        ++compared;
      }
    }
    EXPECT_GE(compared, 60);
  }
}

TEST(MitsubaSky, CarriesToWorldAndBakesScaleIntoTheMap) {
  const SceneDescription plain =
      load_emitters("sky_plain",
                    "<emitter type=\"sky\"><vector name=\"sunDirection\" x=\"0\" y=\"1\" z=\"1\"/>"
                    "<integer name=\"resolution\" value=\"16\"/></emitter>");
  const SceneDescription turned = load_emitters(
      "sky_turned",
      "<emitter type=\"sky\"><vector name=\"sunDirection\" x=\"0\" y=\"-1\" z=\"1\"/>"
      "<integer name=\"resolution\" value=\"16\"/><float name=\"scale\" value=\"3\"/>"
      "<transform name=\"toWorld\"><rotate x=\"1\" angle=\"90\"/></transform></emitter>");
  // The world's (0, -1, 1) is the emitter's (0, 1, 1) under a 90 degree turn about x: the
  // same local sky, three times as bright, turned by toWorld.
  ASSERT_EQ(turned.environment.map.pixels.size(), plain.environment.map.pixels.size());
  for (size_t i = 0; i < plain.environment.map.pixels.size(); ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(turned.environment.map.pixels[i][k], 3.0f * plain.environment.map.pixels[i][k],
                  1e-5f * (1.0f + plain.environment.map.pixels[i][k]));
  EXPECT_EQ(turned.environment.scale, 1.0f);
  const Vec3 up = Vec3(turned.environment.to_world * Vec4(0.0f, 1.0f, 0.0f, 0.0f));
  EXPECT_NEAR(up.z, 1.0f, 1e-6f);
}

TEST(MitsubaSky, RefusesWhatMitsubaRefuses) {
  const auto refusal = [](const std::string& test, const std::string& emitter) {
    return test::error_of([&] { load_emitters(test, emitter); });
  };
  EXPECT_NE(refusal("sky_turbidity",
                    "<emitter type=\"sky\"><float name=\"turbidity\" value=\"11\"/></emitter>")
                .find("'turbidity' must be"),
            std::string::npos);
  EXPECT_NE(refusal("sky_stretch",
                    "<emitter type=\"sunsky\"><float name=\"stretch\" value=\"2.5\"/></emitter>")
                .find("'stretch' must be"),
            std::string::npos);
  EXPECT_NE(refusal("sky_albedo",
                    "<emitter type=\"sky\"><rgb name=\"albedo\" value=\"0.5 1.5 0.5\"/></emitter>")
                .find("'albedo' must lie in [0, 1]"),
            std::string::npos);
  EXPECT_NE(
      refusal("sky_night", "<emitter type=\"sky\"><float name=\"hour\" value=\"1\"/></emitter>")
          .find("below the horizon"),
      std::string::npos);
  EXPECT_NE(refusal("sky_both",
                    "<emitter type=\"sky\"><vector name=\"sunDirection\" x=\"0\" y=\"1\" "
                    "z=\"0\"/><float name=\"latitude\" value=\"10\"/></emitter>")
                .find("'sunDirection' and 'latitude' both given"),
            std::string::npos);
  EXPECT_NE(refusal("sky_two", "<emitter type=\"sun\"/><emitter type=\"sky\"/>")
                .find("a second environment emitter"),
            std::string::npos);
}

// sunRadiusScale 0 makes Mitsuba's sun a directional light: from the sun's direction,
// with the sun's radiance times the solid angle of its disk. `sunDirection` is a world
// direction (Mitsuba takes it into the emitter's frame and toWorld brings it back), so the
// rotation must leave it where it is; a date and place would turn with toWorld.
TEST(MitsubaSky, SunOfRadiusZeroIsADirectionalLight) {
  const SceneDescription sun = load_emitters(
      "sky_directional_sun",
      "<emitter type=\"sun\"><float name=\"sunRadiusScale\" value=\"0\"/>"
      "<vector name=\"sunDirection\" x=\"0\" y=\"1\" z=\"1\"/>"
      "<transform name=\"toWorld\"><rotate y=\"1\" angle=\"90\"/></transform></emitter>");
  EXPECT_EQ(sun.environment.kind, EnvironmentDesc::Kind::None);
  EXPECT_TRUE(sun.divergences.empty());
  ASSERT_EQ(sun.directional_lights.size(), 1u);
  const Vec3 travel = sun.directional_lights[0].direction;
  EXPECT_NEAR(travel.x, 0.0f, 1e-5f);
  EXPECT_NEAR(travel.y, -std::sqrt(0.5f), 1e-5f);
  EXPECT_NEAR(travel.z, -std::sqrt(0.5f), 1e-5f);
  const double radius = kPi / 180.0 * sky::kSunApparentDiameterDegrees / 2.0;
  const Rgb radiance = sky::sun_radiance(kPi / 4.0f, 3.0f);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(sun.directional_lights[0].irradiance[c],
                radiance[c] * 2.0 * kPi * (1.0 - std::cos(radius)), 1e-4 * radiance[c]);
  // sunsky keeps its sky and adds the directional sun.
  const SceneDescription sunsky =
      load_emitters("sky_directional_sunsky",
                    "<emitter type=\"sunsky\"><float name=\"sunRadiusScale\" value=\"0\"/>"
                    "<integer name=\"resolution\" value=\"32\"/></emitter>");
  ASSERT_EQ(sunsky.environment.kind, EnvironmentDesc::Kind::Map);
  EXPECT_EQ(sunsky.directional_lights.size(), 1u);
  // Mitsuba accepts a directional sun beside a sky: so does this.
  const SceneDescription both =
      load_emitters("sky_directional_and_sky",
                    "<emitter type=\"sun\"><float name=\"sunRadiusScale\" value=\"0\"/></emitter>"
                    "<emitter type=\"sky\"><integer name=\"resolution\" value=\"16\"/></emitter>");
  EXPECT_EQ(both.environment.kind, EnvironmentDesc::Kind::Map);
  EXPECT_EQ(both.directional_lights.size(), 1u);
}

// The disk's power does not depend on the map's resolution or on sunRadiusScale (what
// Mitsuba's QMC rasterisation is for): integrated over the sphere, every map carries
// radiance times the sun's solid angle, to within the error of the scheme itself (a
// texel's 1/sin(zenith) density is taken at each point, its area at the texel's centre:
// 4 % off at 64 x 32).
TEST(MitsubaSky, SunPowerIsIndependentOfResolutionAndRadius) {
  const sky::SkyAngles sun{0.7f, 2.0f};
  const Rgb radiance = sky::sun_radiance(sun.zenith, 3.0f);
  const double radius = kPi / 180.0 * sky::kSunApparentDiameterDegrees / 2.0;
  const double expected = radiance.y * 2.0 * kPi * (1.0 - std::cos(radius));
  for (int resolution : {256, 512})
    for (float radius_scale : {1.0f, 5.0f}) {
      Image map(resolution, resolution / 2);
      sky::add_sun(map, sun, radiance, radius_scale);
      double power = 0.0;
      for (int y = 0; y < map.height; ++y) {
        const double theta = (y + 0.5) * kPi / map.height;
        for (int x = 0; x < map.width; ++x)
          power += map.at(x, y).y * std::sin(theta) * (2.0 * kPi / map.width) * (kPi / map.height);
      }
      EXPECT_NEAR(power, expected, 0.01 * expected) << resolution << " " << radius_scale;
    }
}

}  // namespace
}  // namespace emlt
