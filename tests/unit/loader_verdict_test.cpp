// The loader's verdict on a Mitsuba scene: what changes no image (clip planes, sampling
// parameters, what Mitsuba itself ignores, an unused medium) keeps it exact; what does is an
// item.
#include <gtest/gtest.h>

#include "emlt/scene/loaders/loader.h"
#include "support/loader_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::any_contains;
using test::load_and_build_error;
using test::small_xml;
using test::write_file;

}  // namespace

TEST(Loader, MitsubaSettingsThatChangeNoImageKeepTheVerdictExact) {
  const auto dir = test::scratch_dir("exact-settings");
  // Public scenes carry clip planes, a pinhole's focus distance, tone mapping and MLT
  // tuning: none changes the converged image, so the scene stays exact.
  std::string xml = small_xml("");
  xml.replace(xml.find("<float name=\"fov\" value=\"40\"/>"), 0,
              "<float name=\"nearClip\" value=\"0.1\"/><float name=\"farClip\" value=\"100\"/>"
              "<float name=\"focusDistance\" value=\"3\"/>");
  xml.replace(xml.find("<sensor"), 0,
              "<integrator type=\"mlt\"><integer name=\"directSamples\" value=\"4\"/>"
              "<boolean name=\"twoStage\" value=\"true\"/><boolean name=\"strictNormals\" "
              "value=\"false\"/></integrator>\n");
  const SceneDescription exact = load_scene_description(write_file(dir, "exact.xml", xml));
  EXPECT_EQ(exact.verdict(), "exact");
  EXPECT_EQ(exact.render.integrator, "mlt");
  EXPECT_TRUE(any_contains(exact.warnings, "nearClip 0.1 and farClip 100 are not applied"));
  // Mitsuba's MLT does not read strictNormals and treats shading normals strictly, as emlt
  // does then; the parameter is a note.
  EXPECT_TRUE(exact.strict_normals);
  EXPECT_TRUE(any_contains(exact.warnings, "'strictNormals' is not a parameter of Mitsuba's mlt"));
}

// What steers only how Mitsuba samples (a sampler's seed and sequence, a rough BSDF's
// visible-normal sampling, a light's sampling weight, an integrator's sample counts and
// work units) is a note: the scene stays exact and --strict takes it. What changes the
// image is still an item.
TEST(Loader, SamplingOnlyParametersAreNotesNotItems) {
  const auto dir = test::scratch_dir("sampling-only");
  std::string xml = small_xml(R"(
  <shape type="sphere"><bsdf type="roughconductor"><boolean name="sampleVisible" value="false"/></bsdf></shape>
  <shape type="disk"><bsdf type="roughdielectric"><boolean name="sampleVisible" value="true"/></bsdf></shape>
  <shape type="cube"><bsdf type="roughplastic"><boolean name="sampleVisible" value="false"/></bsdf></shape>
  <shape type="rectangle"><transform name="toWorld"><translate z="2"/></transform>
    <emitter type="area"><rgb name="radiance" value="1"/><float name="samplingWeight" value="3"/></emitter></shape>
  <emitter type="constant"><float name="samplingWeight" value="0.5"/></emitter>)");
  xml.replace(xml.find("<film"), 0,
              "<sampler type=\"ldsampler\"><integer name=\"sampleCount\" value=\"4\"/>"
              "<integer name=\"seed\" value=\"7\"/><integer name=\"dimension\" value=\"8\"/>"
              "<integer name=\"scramble\" value=\"3\"/></sampler>");
  const std::string direct =
      R"(<integrator type="direct"><integer name="shadingSamples" value="4"/></integrator>)";
  const std::string mlt =
      R"(<integrator type="mlt"><integer name="workUnits" value="8"/><integer name="timeout" value="60"/>
    <float name="probFactor" value="20"/><integer name="firstStageSizeReduction" value="4"/></integrator>)";
  for (const std::string& integrator : {direct, mlt}) {
    std::string scene = xml;
    scene.replace(scene.find("<sensor"), 0, integrator + "\n  ");
    const SceneDescription desc = load_scene_description(write_file(dir, "exact.xml", scene));
    EXPECT_EQ(desc.verdict(), "exact") << desc.divergences.front().message;
    for (const char* needle :
         {"'sampleVisible' of <bsdf type=\"roughconductor\"> steers only how Mitsuba samples",
          "'sampleVisible' of <bsdf type=\"roughdielectric\">",
          "'sampleVisible' of <bsdf type=\"roughplastic\">",
          "'seed', 'scramble', 'dimension' of <sampler type=\"ldsampler\"> steer only the sample "
          "sequence",
          "'samplingWeight' of <emitter type=\"area\">",
          "'samplingWeight' of <emitter type=\"constant\">"})
      EXPECT_TRUE(any_contains(desc.warnings, needle)) << needle;
    EXPECT_TRUE(any_contains(
        desc.warnings, integrator == direct
                           ? "'shadingSamples'"
                           : "'probFactor', 'firstStageSizeReduction', 'workUnits', 'timeout'"));
  }
  // A malformed value is refused as Mitsuba refuses it.
  std::string malformed = xml;
  malformed.replace(malformed.find("value=\"false\""), 13, "value=\"maybe\"");
  EXPECT_NE(load_and_build_error(write_file(dir, "malformed.xml", malformed))
                .find("'sampleVisible' must be true or false, not 'maybe'"),
            std::string::npos);
  // Beside them, a parameter that changes the image is still counted.
  std::string counted = xml;
  counted.replace(counted.find("<integer name=\"seed\""), 0,
                  "<integer name=\"wobble\" value=\"1\"/>");
  EXPECT_EQ(load_scene_description(write_file(dir, "counted.xml", counted)).verdict(),
            "unsupported: 1 item");
}

TEST(Loader, AMediumIsUnsupportedOnlyWhereSomethingUsesIt) {
  const auto dir = test::scratch_dir("medium");
  const std::string unused = R"(<medium type="homogeneous" id="fog"/>)";
  EXPECT_EQ(load_scene_description(write_file(dir, "unused.xml", small_xml(unused))).verdict(),
            "exact");
  const std::string used = unused + R"(
  <shape type="sphere"><ref name="interior" id="fog"/><bsdf type="dielectric"/></shape>)";
  EXPECT_NE(load_scene_description(write_file(dir, "used.xml", small_xml(used))).verdict(),
            "exact");
}

TEST(Loader, ParametersMitsubaItselfIgnoresKeepTheVerdictExact) {
  const auto dir = test::scratch_dir("mitsuba-ignores");
  // Exporters write roughness onto smooth materials and a file name into the film; Mitsuba's
  // plugins read neither, so ignoring them renders what Mitsuba renders.
  std::string xml = small_xml(R"(
  <shape type="sphere"><bsdf type="dielectric"><float name="alpha" value="0.001"/></bsdf></shape>
  <shape type="disk"><bsdf type="conductor"><float name="alpha" value="0.1"/></bsdf></shape>)");
  xml.replace(xml.find("<rfilter"), 0, "<string name=\"filename\" value=\"out.png\"/>");
  const SceneDescription desc = load_scene_description(write_file(dir, "scene.xml", xml));
  EXPECT_EQ(desc.verdict(), "exact");
  EXPECT_TRUE(any_contains(desc.warnings, "parameter 'alpha' of a smooth dielectric ignored"));
  // On a rough material an unknown parameter is still an unsupported item.
  xml.replace(xml.find("type=\"conductor\""), std::string("type=\"conductor\"").size(),
              "type=\"roughconductor\"><float name=\"wobble\" value=\"1\"/");
  EXPECT_EQ(load_scene_description(write_file(dir, "rough.xml", xml)).verdict(),
            "unsupported: 1 item");
}
