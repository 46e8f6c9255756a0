// Mitsuba 0.6's mixturebsdf and blendbsdf as the loaders read them: the nested BSDFs in the
// file's order, the weights as Mitsuba parses and scales them, a blend's weight as a number
// or a texture, the scene exact; the JSON names give the same material; what Mitsuba refuses
// is refused in one line naming the file, the line and the problem.
#include <gtest/gtest.h>

#include <string>

#include "emlt/core/rng.h"
#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "support/bsdf_loader_checks.h"
#include "support/test_support.h"

using namespace emlt;

using test::expect_same_bsdf;
using test::json_with_material;
using test::subject;
using test::xml_with_bsdf;

namespace {

SceneDescription load(const std::string& name, const std::string& text) {
  const auto dir = test::scratch_dir("weighted-sum-loader");
  return load_scene_description(test::write_file(dir, name, text));
}

std::string error_of_file(const std::string& name, const std::string& text) {
  const auto dir = test::scratch_dir("weighted-sum-loader");
  const std::string path = test::write_file(dir, name, text);
  return test::error_of([&] { load_scene_description(path); });
}

const char* kParts = R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.3, 0.2"/></bsdf>
    <bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/></bsdf>)";

BsdfPtr expected_part(int i) {
  Rgb eta, k;
  conductor_preset("Cu", &eta, &k);
  return i == 0 ? make_lambertian(Rgb(0.8f, 0.3f, 0.2f))
                : make_rough_conductor(make_constant_texture(Rgb(0.2f)), glm::abs(eta / 1.000277f),
                                       glm::abs(k / 1.000277f), make_constant_texture(Rgb(1.0f)),
                                       MicrofacetType::Ggx);
}

}  // namespace

TEST(WeightedSumBsdfLoader, MixtureWeightsAsMitsubaParsesAndScalesThem) {
  // Separated by commas, spaces or semicolons; summing to 1.3, divided by it.
  const SceneDescription scaled = load(
      "mixture.xml",
      xml_with_bsdf(
          std::string(
              R"(<bsdf type="mixturebsdf" id="subject"><string name="weights" value="0.6;0.7"/>)") +
          kParts + "</bsdf>"));
  EXPECT_EQ(scaled.verdict(), "exact");
  EXPECT_EQ(subject(scaled).bsdf->name().rfind("mixture(", 0), 0u) << subject(scaled).bsdf->name();
  expect_same_bsdf(
      *subject(scaled).bsdf,
      *make_mixture({expected_part(0), expected_part(1)}, {0.6f / 1.3f, 0.7f / 1.3f}, false),
      "scaled");
  const SceneDescription kept = load(
      "mixture_kept.xml",
      xml_with_bsdf(
          std::string(
              R"(<bsdf type="mixturebsdf" id="subject"><string name="weights" value="0.6, 0.7"/>
    <boolean name="ensureEnergyConservation" value="false"/>)") +
          kParts + "</bsdf>"));
  EXPECT_EQ(kept.verdict(), "exact");
  expect_same_bsdf(*subject(kept).bsdf,
                   *make_mixture({expected_part(0), expected_part(1)}, {0.6f, 0.7f}, false),
                   "kept");
  // Mitsuba's refusals.
  struct Case {
    std::string weights, problem;
  };
  for (const Case& c :
       std::vector<Case>{{"0.5", "line 9: mixturebsdf has 2 nested BSDFs but 1 weights"},
                         {"0.5 -0.1", "line 10: 'weights' of a mixturebsdf must not be negative"},
                         {"0 0", "line 10: 'weights' of a mixturebsdf must sum to more than 0"},
                         {"0.5 x", "line 10: 'x' is not a number"}}) {
    const std::string message =
        error_of_file("mixture_bad.xml", xml_with_bsdf(R"(<bsdf type="mixturebsdf" id="subject">
    <string name="weights" value=")" + c.weights + "\"/>" +
                                                       kParts + "</bsdf>"));
    EXPECT_NE(message.find("mixture_bad.xml: " + c.problem), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(WeightedSumBsdfLoader, BlendWeightIsANumberOrATexture) {
  const SceneDescription number = load(
      "blend.xml",
      xml_with_bsdf(
          std::string(R"(<bsdf type="blendbsdf" id="subject"><float name="weight" value="0.3"/>)") +
          kParts + "</bsdf>"));
  EXPECT_EQ(number.verdict(), "exact");
  expect_same_bsdf(*subject(number).bsdf, *make_blend(0.3f, expected_part(0), expected_part(1)),
                   "number");
  const SceneDescription defaults = load(
      "blend_default.xml",
      xml_with_bsdf(std::string(R"(<bsdf type="blendbsdf" id="subject">)") + kParts + "</bsdf>"));
  expect_same_bsdf(*subject(defaults).bsdf, *make_blend(0.5f, expected_part(0), expected_part(1)),
                   "default 0.5");
  const SceneDescription textured = load(
      "blend_texture.xml",
      xml_with_bsdf(
          std::string(
              R"(<bsdf type="blendbsdf" id="subject"><texture type="checkerboard" name="weight">
    <rgb name="color0" value="0.1, 0.2, 0.3"/><rgb name="color1" value="0.9"/></texture>)") +
          kParts + "</bsdf>"));
  EXPECT_EQ(textured.verdict(), "exact");
  EXPECT_TRUE(subject(textured).textured);
  expect_same_bsdf(*subject(textured).bsdf, *make_blend(0.2f, expected_part(0), expected_part(1)),
                   "texture color0", BsdfContext{Vec2(0.1f, 0.1f)});
  expect_same_bsdf(*subject(textured).bsdf, *make_blend(0.9f, expected_part(0), expected_part(1)),
                   "texture color1", BsdfContext{Vec2(0.6f, 0.1f)});
  const std::string message = error_of_file(
      "blend_one.xml",
      xml_with_bsdf(R"(<bsdf type="blendbsdf" id="subject"><bsdf type="diffuse"/></bsdf>)"));
  EXPECT_NE(
      message.find("blend_one.xml: line 9: blendbsdf needs exactly two nested BSDFs (it has 1)"),
      std::string::npos)
      << message;
}

TEST(WeightedSumBsdfLoader, MixtureAndBlendInJson) {
  const auto json_with = [](const std::string& material) {
    return R"({"camera": {"lookat": {"origin": [0,0,-5], "target": [0,0,0], "up": [0,1,0]}, "fov": 40},
  "materials": {"subject": )" +
           material + R"(},
  "shapes": [{"type": "rectangle", "emission": [1,1,1]}, {"type": "sphere", "material": "subject"}]})";
  };
  const std::string parts =
      R"([{"type": "diffuse", "reflectance": [0.8, 0.3, 0.2], "two_sided": false},
      {"type": "roughconductor", "material": "Cu", "alpha": 0.2, "distribution": "ggx", "two_sided": false}])";
  const SceneDescription mixture =
      load("mixture.json",
           json_with(R"({"type": "mixture", "weights": [0.6, 0.7], "materials": )" + parts + "}"));
  expect_same_bsdf(*subject(mixture).bsdf,
                   *make_mixture({expected_part(0), expected_part(1)}, {0.6f, 0.7f}),
                   "json mixture");
  const SceneDescription blend = load(
      "blend.json", json_with(R"({"type": "blend", "weight": 0.3, "materials": )" + parts + "}"));
  expect_same_bsdf(*subject(blend).bsdf, *make_blend(0.3f, expected_part(0), expected_part(1)),
                   "json blend");
  const std::string message = error_of_file(
      "mixture_bad.json",
      json_with(R"({"type": "mixture", "weights": [0.6], "materials": )" + parts + "}"));
  EXPECT_NE(message.find("mixture_bad.json"), std::string::npos) << message;
  EXPECT_NE(message.find("expected one number per material"), std::string::npos) << message;
}
