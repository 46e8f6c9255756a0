// Numeric scene parameters outside their valid range (src/scene/parameter_ranges.h) are
// refused by both loaders with one line that names the file and the JSON key or the XML
// line, states the range in words (the command line's words where a flag sets the same
// quantity) and quotes the value; values at the bounds load. Each case fails if its
// check is removed: nothing else refuses these values while a file is loaded.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "emlt/core/error.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

// Every ranged parameter of the JSON format, each at a valid value that occurs once.
constexpr const char* kJson = R"({
  "integrator": {"type": "pt", "max_depth": 6, "rr_depth": 5, "spp": 4},
  "camera": {"lookat": {"origin": [0,0,-5], "target": [0,0,0], "up": [0,1,0]},
    "fov": 40, "aperture_radius": 0.1, "focus_distance": 5, "width": 16, "height": 12,
    "filter": {"type": "gaussian", "stddev": 0.5}},
  "shapes": [
    {"type": "rectangle", "emission": [1,1,1], "material": {"type": "dielectric", "int_ior": 1.5}},
    {"type": "sphere", "radius": 0.25}],
  "environment": {"type": "constant", "radiance": 0.1}
})";

// The same for the Mitsuba format, one parameter a line.
constexpr const char* kXml = R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <integrator type="path">
    <integer name="maxDepth" value="6"/>
    <integer name="rrDepth" value="5"/>
  </integrator>
  <sensor type="thinlens">
    <float name="fov" value="40"/>
    <float name="apertureRadius" value="0.1"/>
    <float name="focusDistance" value="5"/>
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <sampler type="independent"><integer name="sampleCount" value="4"/></sampler>
    <film type="hdrfilm">
      <integer name="width" value="16"/>
      <integer name="height" value="12"/>
      <rfilter type="gaussian"><float name="stddev" value="0.5"/></rfilter>
    </film>
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter>
    <bsdf type="dielectric"><float name="intIOR" value="1.5"/></bsdf></shape>
  <shape type="sphere"><float name="radius" value="0.25"/></shape>
  <shape type="cylinder"><float name="radius" value="0.75"/></shape>
</scene>
)";

// `text` with `from` (which must occur exactly once) replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// 1-based line of the first occurrence of `needle`.
int line_of(const std::string& text, const std::string& needle) {
  const size_t at = text.find(needle);
  if (at == std::string::npos) return 0;
  return 1 + int(std::count(text.begin(), text.begin() + long(at), '\n'));
}

std::string load_error(const std::string& path) {
  try {
    load_scene_description(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

struct Case {
  std::string from, to;  // one parameter of the template, and the value out of range
  std::string message;   // after "<file>: " (JSON) or "<file>: line N: " (XML)
};

}  // namespace

TEST(ParameterRanges, TemplatesLoad) {
  const auto dir = test::scratch_dir("templates");
  EXPECT_EQ(load_error(test::write_file(dir, "scene.json", kJson)), "");
  EXPECT_EQ(load_error(test::write_file(dir, "scene.xml", kXml)), "");
}

TEST(ParameterRanges, JsonValuesOutsideTheirRangeAreRefusedInWords) {
  const auto dir = test::scratch_dir("json");
  const std::vector<Case> cases = {
      {R"("width": 16)", R"("width": 16385)",
       "camera.width: must be a whole number of pixels from 1 to 16384 (got 16385)"},
      {R"("height": 12)", R"("height": 0)",
       "camera.height: must be a whole number of pixels from 1 to 16384 (got 0)"},
      {R"("spp": 4)", R"("spp": 16777217)",
       "integrator.spp: must be a whole number from 1 to 2^24 (about 16.8 million) (got "
       "16777217)"},
      {R"("max_depth": 6)", R"("max_depth": -2)",
       "integrator.max_depth: must be a whole number from 0 to 100000, or -1 for unlimited "
       "(got -2)"},
      {R"("max_depth": 6)", R"("max_depth": 100001)",
       "integrator.max_depth: must be a whole number from 0 to 100000, or -1 for unlimited "
       "(got 100001)"},
      {R"("rr_depth": 5)", R"("rr_depth": 0)",
       "integrator.rr_depth: must be a whole number from 1 to 100000 (got 0)"},
      {R"("fov": 40)", R"("fov": 180)",
       "camera.fov: must be a number of degrees between 0 and 180, both excluded (got 180)"},
      {R"("fov": 40)", R"("fov": -10)",
       "camera.fov: must be a number of degrees between 0 and 180, both excluded (got -10)"},
      {R"("aperture_radius": 0.1)", R"("aperture_radius": -0.5)",
       "camera.aperture_radius: must be zero or a positive number (got -0.5)"},
      {R"("focus_distance": 5)", R"("focus_distance": 0)",
       "camera.focus_distance: must be a positive number (got 0)"},
      {R"("stddev": 0.5)", R"("stddev": 0)",
       "camera.filter.stddev: must be a positive number of pixels, at most 16 (got 0)"},
      {R"({"type": "gaussian", "stddev": 0.5})", R"({"type": "tent", "radius": 65})",
       "camera.filter.radius: must be a positive number of pixels, at most 64 (got 65)"},
      {R"("radius": 0.25)", R"("radius": -1)",
       "shapes[1].radius: must be a positive number (got -1)"},
      {R"("int_ior": 1.5)", R"("int_ior": 0)",
       "shapes[0].material.int_ior: must be a positive number (got 0)"},
      {R"({"type": "constant", "radiance": 0.1})",
       R"({"type": "envmap", "file": "sky.exr", "scale": -1})",
       "environment.scale: must be zero or a positive number (got -1)"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const std::string name = "case" + std::to_string(i) + ".json";
    const std::string path = test::write_file(dir, name, replaced(kJson, c.from, c.to));
    EXPECT_EQ(load_error(path), path + ": " + c.message) << c.to;
  }
}

TEST(ParameterRanges, XmlValuesOutsideTheirRangeAreRefusedAtTheirLineInWords) {
  const auto dir = test::scratch_dir("xml");
  const std::vector<Case> cases = {
      {R"(name="width" value="16")", R"(name="width" value="16385")",
       "'width' must be a whole number of pixels from 1 to 16384 (got 16385)"},
      {R"(name="height" value="12")", R"(name="height" value="0")",
       "'height' must be a whole number of pixels from 1 to 16384 (got 0)"},
      {R"(name="sampleCount" value="4")", R"(name="sampleCount" value="16777217")",
       "'sampleCount' must be a whole number from 1 to 2^24 (about 16.8 million) (got "
       "16777217)"},
      {R"(name="maxDepth" value="6")", R"(name="maxDepth" value="-2")",
       "'maxDepth' must be a whole number from 0 to 100000, or -1 for unlimited (got -2)"},
      {R"(name="maxDepth" value="6")", R"(name="maxDepth" value="100001")",
       "'maxDepth' must be a whole number from 0 to 100000, or -1 for unlimited (got 100001)"},
      {R"(name="rrDepth" value="5")", R"(name="rrDepth" value="0")",
       "'rrDepth' must be a whole number from 1 to 100000 (got 0)"},
      {R"(name="fov" value="40")", R"(name="fov" value="180")",
       "'fov' must be a number of degrees between 0 and 180, both excluded (got 180)"},
      {R"(<float name="fov" value="40"/>)", R"(<string name="focalLength" value="-5mm"/>)",
       "'focalLength' must be a positive length in millimetres, such as 50mm (got -5mm)"},
      {R"(name="apertureRadius" value="0.1")", R"(name="apertureRadius" value="-0.5")",
       "'apertureRadius' must be zero or a positive number (got -0.5)"},
      {R"(name="focusDistance" value="5")", R"(name="focusDistance" value="0")",
       "'focusDistance' must be a positive number (got 0)"},
      {R"(name="stddev" value="0.5")", R"(name="stddev" value="17")",
       "'stddev' must be a positive number of pixels, at most 16 (got 17)"},
      {R"(<rfilter type="gaussian"><float name="stddev" value="0.5"/></rfilter>)",
       R"(<rfilter type="lanczos"><integer name="lobes" value="0"/></rfilter>)",
       "'lobes' must be a whole number from 1 to 64 (got 0)"},
      {R"(name="radius" value="0.25")", R"(name="radius" value="-1")",
       "'radius' must be a positive number (got -1)"},
      {R"(name="radius" value="0.75")", R"(name="radius" value="0")",
       "'radius' must be a positive number (got 0)"},
      {R"(name="intIOR" value="1.5")", R"(name="intIOR" value="-1.5")",
       "'intIOR' must be a positive number (got -1.5)"},
      {R"(<shape type="cylinder"><float name="radius" value="0.75"/></shape>)",
       R"(<shape type="serialized"><string name="filename" value="m.serialized"/>)"
       R"(<integer name="shapeIndex" value="-1"/></shape>)",
       "'shapeIndex' must be a whole number, 0 or more (got -1)"},
      {R"(<shape type="cylinder"><float name="radius" value="0.75"/></shape>)",
       R"(<emitter type="envmap"><string name="filename" value="sky.exr"/>)"
       R"(<float name="scale" value="-1"/></emitter>)",
       "'scale' must be zero or a positive number (got -1)"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const std::string name = "case" + std::to_string(i) + ".xml";
    const std::string text = replaced(kXml, c.from, c.to);
    const std::string path = test::write_file(dir, name, text);
    EXPECT_EQ(load_error(path),
              path + ": line " + std::to_string(line_of(text, c.to)) + ": " + c.message)
        << c.to;
  }
}

// The bounds themselves load, in both formats: the checks refuse nothing the command
// line accepts (--width 16384, --spp 16777216, --max-depth -1 and 100000, --rr-depth 1),
// nor what Mitsuba 0.6 renders and emlt renders too (an unlimited maxDepth).
TEST(ParameterRanges, ValuesAtTheBoundsLoad) {
  const auto dir = test::scratch_dir("bounds");
  std::string json = kJson;
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {R"("width": 16)", R"("width": 16384)"},
           {R"("height": 12)", R"("height": 1)"},
           {R"("spp": 4)", R"("spp": 16777216)"},
           {R"("max_depth": 6)", R"("max_depth": 100000)"},
           {R"("rr_depth": 5)", R"("rr_depth": 1)"},
           {R"("fov": 40)", R"("fov": 179.5)"},
           {R"("aperture_radius": 0.1)", R"("aperture_radius": 0)"},
           {R"("stddev": 0.5)", R"("stddev": 16)"}})
    json = replaced(json, from, to);
  const SceneDescription j = load_scene_description(test::write_file(dir, "upper.json", json));
  EXPECT_EQ(j.camera.width, 16384);
  EXPECT_EQ(j.camera.height, 1);
  EXPECT_EQ(j.render.said("--spp"), "16777216");
  EXPECT_EQ(j.render.said("--max-depth"), "100000");
  EXPECT_EQ(j.render.said("--rr-depth"), "1");
  EXPECT_FLOAT_EQ(j.camera.filter.stddev, 16.0f);

  std::string xml = kXml;
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {R"(name="width" value="16")", R"(name="width" value="1")"},
           {R"(name="height" value="12")", R"(name="height" value="16384")"},
           {R"(name="sampleCount" value="4")", R"(name="sampleCount" value="1")"},
           {R"(name="maxDepth" value="6")", R"(name="maxDepth" value="-1")"},
           {R"(name="rrDepth" value="5")", R"(name="rrDepth" value="100000")"},
           {R"(name="fov" value="40")", R"(name="fov" value="0.5")"},
           {R"(<rfilter type="gaussian"><float name="stddev" value="0.5"/></rfilter>)",
            R"(<rfilter type="lanczos"><integer name="lobes" value="64"/></rfilter>)"}})
    xml = replaced(xml, from, to);
  const SceneDescription x = load_scene_description(test::write_file(dir, "lower.xml", xml));
  EXPECT_EQ(x.camera.width, 1);
  EXPECT_EQ(x.camera.height, 16384);
  EXPECT_EQ(x.render.said("--spp"), "1");
  EXPECT_EQ(x.render.said("--max-depth"), "-1");
  EXPECT_EQ(x.render.said("--rr-depth"), "100000");
  EXPECT_EQ(x.camera.filter.lobes, 64);
}

// A description that no loader checked (built in code) meets the same film bound in
// Scene::build.
TEST(ParameterRanges, SceneBuildRefusesAFilmSideBeyondTheLoadersBound) {
  const auto dir = test::scratch_dir("build");
  SceneDescription desc = load_scene_description(test::write_file(dir, "scene.json", kJson));
  desc.camera.width = 16385;
  try {
    Scene::build(desc);
    ADD_FAILURE() << "a 16385-pixel film was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unusable image resolution 16385x12 (each side must be "
                                         "1 to 16384 pixels)"),
              std::string::npos)
        << e.what();
  }
}
