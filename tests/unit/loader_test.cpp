// Scene loaders in general: `$name` defines in either format, bad input gives a one-line
// error naming the file, unsupported Mitsuba features are reported with their name and line.
#include "emlt/scene/loaders/loader.h"

#include <gtest/gtest.h>

#include "emlt/core/error.h"
#include "emlt/scene/scene.h"
#include "support/loader_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::any_contains;
using test::error_of;
using test::load_and_build_error;
using test::small_json;
using test::small_xml;
using test::write_file;

constexpr const char* kLightOnlyObj = "v 0 1 0\nv 1 1 0\nv 0 1 1\nf 1 3 2\n";

}  // namespace

TEST(Loader, DefinesOverrideDefaultsInXmlAndJson) {
  const SceneDefines defines = {{"width", "64"}, {"height", "48"}, {"spp", "4"}};
  for (const char* file : {"scenes/cornell-box/scene.xml", "scenes/cornell-box/scene.json"}) {
    const SceneDescription desc = load_scene_description(test::source_path(file), defines);
    EXPECT_EQ(desc.camera.width, 64) << file;
    EXPECT_EQ(desc.camera.height, 48) << file;
    EXPECT_EQ(desc.render.said("--spp"), "4") << file;
  }
  const auto dir = test::scratch_dir("defines");
  const std::string json =
      write_file(dir, "undefined.json", small_json(R"(, "width": "$size")", ""));
  const std::string message = error_of([&] { load_scene_description(json); });
  EXPECT_NE(message.find("undefined.json"), std::string::npos) << message;
  EXPECT_NE(message.find("$size"), std::string::npos) << message;
  EXPECT_EQ(load_scene_description(json, {{"size", "20"}}).camera.width, 20);

  const std::string xml = write_file(dir, "param.xml", small_xml(R"(
  <shape type="sphere"><float name="radius" value="$r"/><point name="center" x="$x" y="0" z="0"/></shape>
  <default name="r" value="0.25"/>)"));
  SceneDescription desc = load_scene_description(xml, {{"x", "3"}});
  ASSERT_EQ(desc.spheres.size(), 1u);
  EXPECT_FLOAT_EQ(desc.spheres[0].radius, 0.25f);
  EXPECT_FLOAT_EQ(desc.spheres[0].center.x, 3.0f);
  const std::string missing = error_of([&] { load_scene_description(xml); });
  EXPECT_NE(missing.find("param.xml: line 11"), std::string::npos) << missing;
  EXPECT_NE(missing.find("$x"), std::string::npos) << missing;
}

TEST(Loader, BadInputGivesOneLineErrorNamingFileAndProblem) {
  const auto dir = test::scratch_dir("bad");
  write_file(dir, "light.obj", kLightOnlyObj);
  std::string absurd_xml = small_xml("");
  for (size_t at; (at = absurd_xml.find("value=\"16\"")) != std::string::npos;)
    absurd_xml.replace(at, 10, "value=\"100000\"");
  struct Case {
    std::string file, content, expected_file, expected_problem;
  };
  const std::vector<Case> cases = {
      {"malformed.json", R"({"camera": {"fov": 40,)", "malformed.json", "malformed JSON"},
      {"malformed.xml", "<scene version=\"0.6.0\">\n<shape type=\"obj\">\n</scene>\n",
       "malformed.xml", "malformed XML at line 3"},
      {"missing_obj.json", small_json("", R"(, {"type": "obj", "file": "nowhere.obj"})"),
       "nowhere.obj", "not found"},
      {"missing_obj.xml",
       small_xml(R"(<shape type="obj"><string name="filename" value="nowhere.obj"/></shape>)"),
       "nowhere.obj", "not found"},
      {"missing_env.json",
       small_json("", "").replace(1, 0,
                                  R"("environment": {"type": "envmap", "file": "sky.exr"}, )"),
       "missing_env.json", "environment map"},
      {"missing_env.xml",
       small_xml(R"(<emitter type="envmap"><string name="filename" value="sky.exr"/></emitter>)"),
       "sky.exr", "not found"},
      {"nan_transform.json",
       small_json("", R"(, {"type": "cube", "transform": [{"scale": 1e39}]})"),
       "nan_transform.json", "NaN"},
      {"nan_transform.xml",
       small_xml(
           R"(<shape type="cube"><transform name="toWorld"><translate x="nan"/></transform></shape>)"),
       "nan_transform.xml", "not a finite number"},
      {"nan_camera.json",
       R"({"camera": {"lookat": {"origin": [0,0,0], "target": [0,1,0], "up": [0,1,0]}},
         "shapes": [{"type": "rectangle", "emission": 1}]})",
       "nan_camera.json", "NaN"},
      {"no_emitter.json", R"({"shapes": [{"type": "cube"}]})", "no_emitter.json",
       "scene has no emitter"},
      {"no_emitter.xml", "<scene version=\"0.6.0\"><shape type=\"cube\"/></scene>",
       "no_emitter.xml", "scene has no emitter"},
      {"zero_resolution.json", small_json(R"(, "width": 0)", ""), "zero_resolution.json",
       "camera.width: must be a whole number of pixels from 1 to 16384 (got 0)"},
      {"absurd_resolution.json", small_json(R"(, "width": 100000, "height": 100000)", ""),
       "absurd_resolution.json", "camera.width: must be a whole number of pixels from 1 to 16384"},
      {"absurd_resolution.xml", absurd_xml, "absurd_resolution.xml",
       "line 6: 'width' must be a whole number of pixels from 1 to 16384 (got 100000)"},
      {"unknown_material.json", small_json("", R"(, {"type": "cube", "material": "nope"})"),
       "unknown_material.json", "unknown material 'nope'"},
      {"unknown_material.xml", small_xml(R"(<shape type="cube"><ref id="nope"/></shape>)"),
       "unknown_material.xml", "unknown reference id 'nope'"},
      {"bad_index.json", small_json("", R"(, {"type": "obj", "file": "bad_index.obj"})"),
       "bad_index.obj", "out of range"},
      {"wrong_type.json", small_json("", R"(, {"type": "sphere", "radius": "big"})"),
       "wrong_type.json", "shapes[1].radius: expected a number"},
      {"missing_key.json", small_json("", R"(, {"type": "obj"})"), "missing_key.json",
       "missing required key 'file'"},
      {"no_faces.json", small_json("", R"(, {"type": "obj", "file": "empty.obj"})"), "empty.obj",
       "no faces"},
  };
  write_file(dir, "bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  write_file(dir, "empty.obj", "v 0 0 0\nv 1 0 0\n");
  for (const Case& c : cases) {
    const std::string path = write_file(dir, c.file, c.content);
    const std::string message = load_and_build_error(path);
    EXPECT_NE(message.find(c.expected_file), std::string::npos) << c.file << ": " << message;
    EXPECT_NE(message.find(c.expected_problem), std::string::npos) << c.file << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << c.file << ": " << message;
  }
  EXPECT_NE(load_and_build_error((dir / "scene.obj").string()).find("unknown scene format"),
            std::string::npos);
  EXPECT_NE(
      load_and_build_error((dir / "absent.json").string()).find("absent.json: file not found"),
      std::string::npos);
}

TEST(Loader, UnsupportedMitsubaElementsAreReportedWithNameAndLine) {
  const auto dir = test::scratch_dir("mitsuba-warnings");
  const std::string xml = write_file(dir, "scene.xml", small_xml(R"(
  <shape type="heightfield"><string name="filename" value="x.exr"/></shape>
  <medium type="homogeneous" id="fog"/>
  <emitter type="laser"><rgb name="power" value="1"/></emitter>
  <shape type="cube"><bsdf type="hk"/><float name="wobble" value="2"/></shape>
  <shape type="sphere"><bsdf type="roughconductor"><string name="distribution" value="trowbridge"/></bsdf></shape>
  <shape type="disk"><bsdf type="roughplastic"><float name="alphaU" value="0.1"/><float name="alphaV" value="0.3"/></bsdf></shape>)"));
  const SceneDescription desc = load_scene_description(xml);
  for (const char* needle : {"'heightfield'", "<medium", "'laser'", "'hk'", "'wobble'",
                             "distribution 'trowbridge'", "anisotropic roughness"})
    EXPECT_TRUE(any_contains(desc.warnings, needle)) << needle;
  EXPECT_TRUE(any_contains(desc.warnings, "scene.xml: line 11:"))
      << desc.warnings.front();       // the heightfield shape
  EXPECT_EQ(desc.meshes.size(), 3u);  // emissive rectangle, cube, disk (the heightfield is skipped)
  EXPECT_EQ(desc.spheres.size(), 1u);

  const std::string json = write_file(dir, "scene.json", small_json(R"(, "colour": 3)", ""));
  EXPECT_TRUE(
      any_contains(load_scene_description(json).warnings, "unknown key 'colour' in camera"));
}

TEST(Loader, SceneWhoseShapesWereAllSkippedNamesThem) {
  const auto dir = test::scratch_dir("all-skipped");
  const std::string path = write_file(dir, "skipped.xml", R"(<scene version="0.6.0">
  <emitter type="constant"/>
  <shape type="heightfield"/>
  <shape type="hair"><string name="filename" value="x.hair"/></shape>
</scene>)");
  EXPECT_NE(load_and_build_error(path).find(
                "skipped.xml: scene has no geometry: every shape was skipped (<shape "
                "type=\"heightfield\"> at line 3, <shape type=\"hair\"> at line 4)"),
            std::string::npos)
      << load_and_build_error(path);
}
