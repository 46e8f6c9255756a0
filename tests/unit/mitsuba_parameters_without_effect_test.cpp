// Parameters of Mitsuba 0.6 plugins read as Mitsuba reads them: the scale texture's `value`
// (the colour it scales, unless a nested texture takes its place), a cube's faceNormals and a
// constant emitter's toWorld (both change nothing in Mitsuba either), and an area emitter's
// toWorld, which Mitsuba refuses.
#include <gtest/gtest.h>

#include <string>

#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "support/bsdf_loader_checks.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

std::string scene(const std::string& body) {
  return R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
  )" + body +
         "\n</scene>\n";
}

std::string write(const std::string& name, const std::string& body) {
  return test::write_file(test::scratch_dir("parameters-without-effect"), name, scene(body));
}

const char* kLight =
    R"(<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)";

}  // namespace

TEST(MitsubaParametersWithoutEffect, ScaleTextureScalesItsValueOrItsNestedTexture) {
  const SceneDescription value = load_scene_description(write("value.xml", std::string(kLight) + R"(
    <bsdf type="diffuse" id="subject"><texture type="scale" name="reflectance">
      <float name="scale" value="0.5"/><rgb name="value" value="0.8, 0.4, 0.2"/></texture></bsdf>
    <shape type="sphere"><ref id="subject"/></shape>)"));
  EXPECT_EQ(value.verdict(), "exact");
  test::expect_same_bsdf(*test::subject(value).bsdf, *make_lambertian(Rgb(0.4f, 0.2f, 0.1f)),
                         "scaled value");

  // A nested texture takes the value's place: the last one given, named or not.
  const SceneDescription nested =
      load_scene_description(write("nested.xml", std::string(kLight) + R"(
    <bsdf type="diffuse" id="subject"><texture type="scale" name="reflectance">
      <float name="scale" value="0.5"/><rgb name="value" value="0.8, 0.4, 0.2"/>
      <texture type="checkerboard" name="value">
        <rgb name="color0" value="0.9"/><rgb name="color1" value="0.9"/></texture>
      <texture type="checkerboard">
        <rgb name="color0" value="0.6"/><rgb name="color1" value="0.6"/></texture>
    </texture></bsdf>
    <shape type="sphere"><ref id="subject"/></shape>)"));
  EXPECT_EQ(nested.verdict(), "exact");
  test::expect_same_bsdf(*test::subject(nested).bsdf, *make_lambertian(Rgb(0.3f)),
                         "the last nested texture, scaled");
}

TEST(MitsubaParametersWithoutEffect, CubeFaceNormalsAndConstantToWorldChangeNothing) {
  const SceneDescription plain =
      load_scene_description(write("cube.xml", std::string(kLight) + R"(<shape type="cube"/>)"));
  const SceneDescription faces = load_scene_description(
      write("cube_faces.xml",
            std::string(kLight) +
                R"(<shape type="cube"><boolean name="faceNormals" value="true"/></shape>)"));
  EXPECT_EQ(faces.verdict(), "exact");
  ASSERT_EQ(faces.meshes.size(), plain.meshes.size());
  EXPECT_EQ(faces.meshes.back().positions, plain.meshes.back().positions);
  EXPECT_EQ(faces.meshes.back().normals, plain.meshes.back().normals);

  const SceneDescription sky = load_scene_description(write("constant.xml", R"(
    <emitter type="constant"><rgb name="radiance" value="0.5"/>
      <transform name="toWorld"><rotate y="1" angle="30"/></transform></emitter>
    <shape type="sphere"/>)"));
  EXPECT_EQ(sky.verdict(), "exact");
  EXPECT_EQ(sky.environment.kind, EnvironmentDesc::Kind::Constant);
}

TEST(MitsubaParametersWithoutEffect, AreaEmitterToWorldIsRefusedAsMitsubaRefusesIt) {
  const std::string path = write("area.xml", R"(<shape type="rectangle"><emitter type="area">
      <rgb name="radiance" value="1"/>
      <transform name="toWorld"><translate y="1"/></transform></emitter></shape>)");
  const std::string error = test::error_of([&] { load_scene_description(path); });
  EXPECT_NE(error.find("area.xml: line 9"), std::string::npos) << error;
  EXPECT_NE(error.find("an area emitter takes no 'toWorld'"), std::string::npos) << error;
}
