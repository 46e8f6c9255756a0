// Mitsuba 3 XML (version 2.x/3.x) read through the 0.6 loader: snake_case names mean what
// their 0.6 names mean, what Mitsuba 3 does not read is an item of the verdict naming file
// and line, and the meanings Mitsuba 3 changed are Mitsuba 3's. The conformance twins
// (tests/conformance/check_mitsuba3.py) check whole scenes to the bit.
#include <gtest/gtest.h>

#include <cmath>

#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

// A small Mitsuba 3 scene: `sensor` inside the sensor, `body` after an area light.
std::string mi3_xml(const std::string& body, const std::string& sensor = "",
                    const std::string& version = "3.0.0") {
  return R"(<?xml version="1.0"?>
<scene version=")" +
         version + R"(">
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="16"/>
      <rfilter type="box"/></film>)" +
         sensor + R"(
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter>
    <bsdf type="diffuse"/></shape>
)" + body +
         "\n</scene>\n";
}

SceneDescription load(const std::string& name, const std::string& xml) {
  return load_scene_description(test::write_file(test::scratch_dir("mitsuba3"), name, xml));
}

// The divergence whose message contains `needle`, or null.
const Divergence* item(const SceneDescription& d, const std::string& needle) {
  for (const Divergence& v : d.divergences)
    if (v.message.find(needle) != std::string::npos) return &v;
  return nullptr;
}

bool noted(const SceneDescription& d, const std::string& needle) {
  for (const std::string& w : d.warnings)
    if (w.find(needle) != std::string::npos) return true;
  return false;
}

std::string all_items(const SceneDescription& d) {
  std::string text;
  for (const Divergence& v : d.divergences) text += v.message + "\n";
  return text;
}

TEST(Mitsuba3Loader, CornellBoxIsExactAndBuildsThe06Scene) {
  const SceneDescription mi3 =
      load_scene_description(test::source_path("scenes/cornell-box/scene-mitsuba3.xml"));
  const SceneDescription mi06 =
      load_scene_description(test::source_path("scenes/cornell-box/scene.xml"));
  EXPECT_EQ(mi3.verdict(), "exact") << all_items(mi3);
  EXPECT_EQ(mi3.render.said("--spp"), "64");  // <default name="spp" value="64"/>, $spp
  EXPECT_EQ(mi3.render.said("--max-depth"), "-1");
  EXPECT_EQ(mi3.render.integrator, "pt");
  EXPECT_EQ(mi3.camera.to_world, mi06.camera.to_world);
  EXPECT_EQ(mi3.camera.fov_degrees, mi06.camera.fov_degrees);
  EXPECT_EQ(mi3.camera.width, mi06.camera.width);
  ASSERT_EQ(mi3.meshes.size(), mi06.meshes.size());
  for (size_t i = 0; i < mi3.meshes.size(); ++i) {
    EXPECT_EQ(mi3.meshes[i].positions, mi06.meshes[i].positions) << i;
    EXPECT_EQ(mi3.meshes[i].normals, mi06.meshes[i].normals) << i;  // face_normals: none
    EXPECT_EQ(mi3.meshes[i].emission, mi06.meshes[i].emission) << i;
  }
  EXPECT_EQ(mi3.materials.size(), mi06.materials.size());
}

TEST(Mitsuba3Loader, SnakeCaseNamesMeanTheir06Names) {
  const SceneDescription d = load("names.xml", mi3_xml(R"(
  <integrator type="path"><integer name="max_depth" value="3"/><integer name="rr_depth" value="2"/>
    <boolean name="hide_emitters" value="true"/></integrator>
  <shape type="sphere"><float name="radius" value="0.5"/><boolean name="flip_normals" value="true"/>
    <transform name="to_world"><translate x="2"/></transform></shape>)",
                                                       R"(
    <string name="fov_axis" value="y"/>
    <sampler type="independent"><integer name="sample_count" value="9"/>
      <integer name="seed" value="4"/></sampler>)"));
  EXPECT_EQ(d.verdict(), "exact") << all_items(d);
  EXPECT_EQ(d.render.said("--max-depth"), "3");
  EXPECT_EQ(d.render.said("--rr-depth"), "2");
  EXPECT_EQ(d.render.said("--hide-emitters"), "true");
  EXPECT_EQ(d.render.said("--spp"), "9");
  EXPECT_EQ(d.camera.fov_axis, CameraDesc::FovAxis::Y);
  ASSERT_EQ(d.spheres.size(), 1u);
  EXPECT_EQ(d.spheres[0].center, Vec3(2.0f, 0.0f, 0.0f));
  EXPECT_TRUE(d.spheres[0].flip_normals);
  EXPECT_TRUE(noted(d, "'seed'"));  // the sampler's seed: a note, not an item
}

TEST(Mitsuba3Loader, NamesMitsuba3DoesNotReadAreItemsWithFileAndLine) {
  // 0.6's camelCase in a version 3 file: Mitsuba 3 ignores it, so emlt must not apply it.
  const SceneDescription d = load("camel.xml", mi3_xml(R"(
  <integrator type="path"><integer name="maxDepth" value="3"/></integrator>
  <shape type="sphere"><transform name="toWorld"><translate x="2"/></transform></shape>)"));
  const Divergence* to_world = item(d, "'toWorld'");
  ASSERT_NE(to_world, nullptr) << all_items(d);
  EXPECT_NE(to_world->message.find("camel.xml: line 13"), std::string::npos) << to_world->message;
  EXPECT_NE(to_world->message.find("Mitsuba 3"), std::string::npos) << to_world->message;
  EXPECT_NE(item(d, "'maxDepth'"), nullptr) << all_items(d);
  EXPECT_EQ(d.render.said("--max-depth"), std::nullopt);
  ASSERT_EQ(d.spheres.size(), 1u);
  EXPECT_EQ(d.spheres[0].center, Vec3(0.0f));
  // The same file as 0.6 reads both.
  std::string as06 = mi3_xml(R"(
  <integrator type="path"><integer name="maxDepth" value="3"/></integrator>
  <shape type="sphere"><transform name="toWorld"><translate x="2"/></transform></shape>)",
                             "", "0.6.0");
  as06.replace(as06.find("to_world"), 8, "toWorld");
  const SceneDescription d06 = load("camel06.xml", as06);
  EXPECT_EQ(d06.verdict(), "exact") << all_items(d06);
  EXPECT_EQ(d06.spheres[0].center, Vec3(2.0f, 0.0f, 0.0f));
}

TEST(Mitsuba3Loader, PluginsAndFormsMitsuba3DroppedAreItems) {
  const SceneDescription d = load("dropped.xml", mi3_xml(R"(
  <integrator type="bdpt"/>
  <shape type="sphere"><bsdf type="phong"/></shape>
  <shape type="sphere"><float name="radius" value="0.3"/>
    <bsdf type="diffuse"><srgb name="reflectance" value="#808080"/></bsdf></shape>
  <shape type="sphere"><float name="radius" value="0.2"/>
    <bsdf type="roughconductor"><string name="distribution" value="phong"/></bsdf></shape>)"));
  EXPECT_NE(item(d, "<integrator type=\"bdpt\">"), nullptr) << all_items(d);
  EXPECT_NE(item(d, "<bsdf type=\"phong\">"), nullptr) << all_items(d);
  EXPECT_NE(item(d, "<srgb>"), nullptr) << all_items(d);
  EXPECT_NE(item(d, "distribution 'phong'"), nullptr) << all_items(d);
  EXPECT_EQ(d.render.integrator, "bdpt");  // still rendered as 0.6 means it
}

TEST(Mitsuba3Loader, ChangedMeaningsAreMitsuba3s) {
  // A uniform spectrum on an emitter is D65-white tinted in Mitsuba 3's RGB variants; the
  // focal length spans the 36 x 24 mm diagonal; a conductor without a material is a mirror.
  const SceneDescription d = load("meanings.xml", mi3_xml(R"(
  <shape type="sphere"><emitter type="area"><spectrum name="radiance" value="2"/></emitter></shape>
  <shape type="sphere"><float name="radius" value="0.2"/><bsdf type="conductor"/></shape>
  <shape type="sphere"><float name="radius" value="0.1"/>
    <bsdf type="roughconductor"><boolean name="sample_visible" value="false"/>
      <string name="material" value="Au"/></bsdf></shape>)"));
  ASSERT_EQ(d.spheres.size(), 3u);
  EXPECT_NEAR(d.spheres[0].emission.x, 2.0f * 1.204794f, 1e-5f);
  EXPECT_NEAR(d.spheres[0].emission.y, 2.0f * 0.948291f, 1e-5f);
  EXPECT_NEAR(d.spheres[0].emission.z, 2.0f * 0.908916f, 1e-5f);
  EXPECT_EQ(item(d, "'sample_visible'"), nullptr) << all_items(d);  // a note
  const Divergence* au = item(d, "material 'Au'");
  ASSERT_NE(au, nullptr) << all_items(d);
  EXPECT_EQ(au->kind, Divergence::Kind::Approximated);
  EXPECT_EQ(d.divergences.size(), 1u) << all_items(d);

  std::string focal = mi3_xml("");
  const std::string fov = R"(<float name="fov" value="40"/>)";
  focal.replace(focal.find(fov), fov.size(), R"(<string name="focal_length" value="35mm"/>)");
  const SceneDescription lens = load("focal.xml", focal);
  // 2 atan(43.27 / 70) across the diagonal of a 32 x 16 image, as horizontal fov.
  const double diagonal = 2.0 * std::atan(std::hypot(36.0, 24.0) / 70.0);
  const double horizontal =
      2.0 * std::atan(std::tan(diagonal / 2.0) * 32.0 / std::hypot(32.0, 16.0));
  EXPECT_NEAR(lens.camera.fov_degrees, horizontal * 180.0 / M_PI, 1e-3) << all_items(lens);
}

TEST(Mitsuba3Loader, Version2IsMitsuba3sDialect) {
  const SceneDescription d = load("v2.xml", mi3_xml(R"(
  <shape type="sphere"><transform name="to_world"><translate y="1"/></transform></shape>)",
                                                    "", "2.1.0"));
  EXPECT_EQ(d.verdict(), "exact") << all_items(d);
  EXPECT_EQ(d.spheres[0].center, Vec3(0.0f, 1.0f, 0.0f));
}

}  // namespace
