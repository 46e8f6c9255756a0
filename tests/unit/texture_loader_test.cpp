// Loading the Mitsuba material vocabulary added with textures, and the JSON
// format's texture objects: everything here must load without a single warning and
// build the intended BSDFs, textures, masks and bump maps.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "emlt/core/error.h"
#include "emlt/image/image.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::write_file;

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

void write_test_images(const std::filesystem::path& dir) {
  Image checker(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) checker.at(x, y) = Rgb((x + y) % 2 ? 0.8f : 0.2f);
  write_image((dir / "checker.png").string(), checker);
  write_image((dir / "height.pfm").string(), checker);
  // One quad with texture coordinates; vt v = 0 is the image's bottom in OBJ.
  write_file(dir, "quad.obj",
             "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
             "f 1/1 2/2 3/3 4/4\n");
}

constexpr const char* kXml = R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
      <rfilter type="box"/></film>
  </sensor>
  <texture type="bitmap" id="checker_png">
    <string name="filename" value="checker.png"/>
    <float name="uvscale" value="2"/><float name="uoffset" value="0.25"/>
    <string name="filterType" value="trilinear"/>
  </texture>
  <texture type="checkerboard" id="checks">
    <rgb name="color0" value="0.7, 0.6, 0.5"/><srgb name="color1" value="#202020"/>
    <float name="uscale" value="4"/><float name="vscale" value="4"/>
  </texture>
  <bsdf type="twosided" id="walls">
    <bsdf type="diffuse"><ref name="reflectance" id="checker_png"/></bsdf>
  </bsdf>
  <bsdf type="roughplastic" id="floor">
    <string name="distribution" value="ggx"/><float name="alpha" value="0.2"/>
    <boolean name="nonlinear" value="true"/>
    <float name="intIOR" value="1.5"/><string name="extIOR" value="air"/>
    <texture type="scale" name="diffuseReflectance">
      <spectrum name="scale" value="0.5"/>
      <ref id="checks"/>
    </texture>
    <spectrum name="specularReflectance" value="0.9 0.9 0.8"/>
  </bsdf>
  <bsdf type="bumpmap" id="teapot">
    <texture type="scale"><float name="scale" value="0.01"/>
      <texture type="bitmap"><string name="filename" value="height.pfm"/></texture>
    </texture>
    <bsdf type="roughconductor">
      <string name="material" value="Fe"/><float name="alpha" value="0.15"/>
      <texture type="checkerboard" name="specularReflectance">
        <float name="color0" value="1"/><float name="color1" value="0.8"/></texture>
    </bsdf>
  </bsdf>
  <bsdf type="roughdielectric" id="frosted">
    <string name="distribution" value="beckmann"/><float name="alpha" value="0.1"/>
    <string name="intIOR" value="bk7"/>
  </bsdf>
  <shape type="obj"><string name="filename" value="quad.obj"/><ref id="walls"/></shape>
  <shape type="rectangle"><ref id="floor"/></shape>
  <shape type="sphere"><ref id="teapot"/></shape>
  <shape type="sphere"><point name="center" x="3" y="0" z="0"/><ref id="frosted"/></shape>
  <shape type="cube"><bsdf type="thindielectric"><float name="intIOR" value="1.5"/></bsdf></shape>
  <shape type="disk"><bsdf type="conductor"><string name="material" value="Ti"/></bsdf></shape>
  <shape type="disk"><bsdf type="conductor"><spectrum name="eta" value="0.2 0.9 1.1"/>
    <spectrum name="k" value="3.9, 2.45, 2.14"/><rgb name="specularReflectance" value="0.9"/></bsdf></shape>
  <shape type="disk"><bsdf type="conductor"><string name="material" value="none"/></bsdf></shape>
  <shape type="disk"><bsdf type="roughconductor"><string name="material" value="W"/>
    <texture type="bitmap" name="alpha"><string name="filename" value="checker.png"/>
      <float name="gamma" value="2.2"/></texture></bsdf></shape>
  <shape type="disk"><bsdf type="dielectric"/></shape>
  <shape type="disk">
    <bsdf type="mask"><texture type="bitmap" name="opacity"><string name="filename" value="checker.png"/></texture>
      <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.2 0.3 0.4"/></bsdf></bsdf>
    </bsdf>
  </shape>
  <shape type="rectangle"><transform name="toWorld"><translate z="5"/></transform>
    <emitter type="area"><spectrum name="radiance" value="2"/></emitter><bsdf type="diffuse"/></shape>
</scene>
)";

const MaterialDesc* find_material(const SceneDescription& d, const std::string& name) {
  for (const MaterialDesc& m : d.materials)
    if (m.name == name) return &m;
  return nullptr;
}

TEST(TextureLoader, MitsubaMaterialVocabularyLoadsWithoutWarnings) {
  const auto dir = test::scratch_dir("texture-loader-xml");
  write_test_images(dir);
  const std::string path = write_file(dir, "scene.xml", kXml);
  SceneDescription desc = load_scene_description(path);
  EXPECT_TRUE(desc.warnings.empty()) << joined(desc.warnings);

  const MaterialDesc* walls = find_material(desc, "walls");
  ASSERT_TRUE(walls);
  EXPECT_EQ(walls->bsdf->name(), "two_sided(lambertian)");
  EXPECT_TRUE(walls->textured);
  const MaterialDesc* floor = find_material(desc, "floor");
  ASSERT_TRUE(floor);
  EXPECT_EQ(floor->bsdf->name(), "rough_plastic");
  EXPECT_TRUE(floor->textured);
  const MaterialDesc* teapot = find_material(desc, "teapot");
  ASSERT_TRUE(teapot);
  EXPECT_EQ(teapot->bsdf->name(), "rough_conductor_beckmann");  // Mitsuba's default
  ASSERT_TRUE(teapot->bump);
  EXPECT_NEAR(teapot->bump->eval(Vec2(0.125f, 0.125f)).x, 0.002f, 1e-6f);  // 0.01 x 0.2
  EXPECT_EQ(find_material(desc, "frosted")->bsdf->name(), "rough_dielectric_beckmann");

  std::vector<std::string> names;
  const MaterialDesc* masked = nullptr;
  for (const MaterialDesc& m : desc.materials) {
    names.push_back(m.bsdf->name());
    if (m.opacity) masked = &m;
  }
  for (const char* expected : {"thin_dielectric", "conductor", "dielectric"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  ASSERT_TRUE(masked);
  EXPECT_EQ(masked->bsdf->name(), "two_sided(lambertian)");  // the inner BSDF
  EXPECT_TRUE(masked->textured);

  // OBJ vt are flipped (Mitsuba's flipTexCoords): vt (0, 0) becomes uv (0, 1).
  ASSERT_EQ(desc.meshes[0].uvs.size(), 4u);
  EXPECT_EQ(desc.meshes[0].uvs[0], Vec2(0.0f, 1.0f));

  const auto scene = Scene::build(std::move(desc));
  EXPECT_TRUE(scene->warnings().empty()) << joined(scene->warnings());
}

TEST(TextureLoader, UnsupportedTextureIsNamedWithItsLine) {
  const auto dir = test::scratch_dir("texture-loader-unknown");
  std::string xml = kXml;
  xml.replace(xml.find("<bsdf type=\"dielectric\"/>"), 25,
              "<bsdf type=\"diffuse\"><texture type=\"wireframe\" name=\"reflectance\">"
              "<float name=\"lineWidth\" value=\"0.1\"/></texture></bsdf>");
  write_test_images(dir);
  const auto at = xml.find("wireframe");
  const std::string line = "line " + std::to_string(1 + std::count(xml.begin(), xml.begin() + at, '\n'));
  const SceneDescription desc = load_scene_description(write_file(dir, "scene.xml", xml));
  ASSERT_EQ(desc.warnings.size(), 1u) << joined(desc.warnings);  // once, parameters included
  EXPECT_NE(desc.warnings[0].find("'wireframe'"), std::string::npos);
  EXPECT_NE(desc.warnings[0].find("scene.xml: " + line + ":"), std::string::npos) << desc.warnings[0];
}

TEST(TextureLoader, MissingTextureImageIsAnErrorNamingIt) {
  const auto dir = test::scratch_dir("texture-loader-missing");
  const std::string path = write_file(dir, "scene.xml", kXml);  // no images written
  try {
    load_scene_description(path);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("checker.png"), std::string::npos) << e.what();
  }
}

TEST(TextureLoader, JsonAcceptsTexturesWhereverAColourGoes) {
  const auto dir = test::scratch_dir("texture-loader-json");
  write_test_images(dir);
  const std::string path = write_file(dir, "scene.json", R"({
  "camera": {"lookat": {"origin": [0,0,-5], "target": [0,0,0]}, "width": 8, "height": 8},
  "materials": {
    "checks": {"type": "diffuse", "reflectance": {"type": "checkerboard", "color0": 0.8, "color1": [0.1, 0.2, 0.3], "uvscale": 4}},
    "wood": {"type": "roughplastic", "alpha": 0.2, "nonlinear": true, "distribution": "beckmann",
             "diffuse_reflectance": {"type": "bitmap", "file": "checker.png", "uscale": 2, "voffset": 0.5}},
    "metal": {"type": "roughconductor", "material": "Ni",
              "alpha": {"type": "scale", "scale": 0.5, "texture": {"type": "bitmap", "file": "checker.png", "raw": true}},
              "bump": {"type": "scale", "scale": 0.01, "texture": {"type": "bitmap", "file": "height.pfm"}}},
    "leaf": {"type": "diffuse", "opacity": {"type": "bitmap", "file": "checker.png", "wrap": "clamp"}},
    "frosted": {"type": "roughdielectric", "alpha": 0.2, "int_ior": 1.5},
    "pane": {"type": "thindielectric"},
    "gold": {"type": "conductor", "material": "Au"}
  },
  "shapes": [
    {"type": "obj", "file": "quad.obj", "material": "checks"},
    {"type": "rectangle", "material": "wood"},
    {"type": "sphere", "material": "metal"},
    {"type": "disk", "material": "leaf"},
    {"type": "disk", "material": "frosted"},
    {"type": "disk", "material": "pane"},
    {"type": "disk", "material": "gold"},
    {"type": "rectangle", "emission": 1, "material": "checks", "transform": [{"translate": [0, 0, 5]}]}
  ]})");
  SceneDescription desc = load_scene_description(path);
  EXPECT_TRUE(desc.warnings.empty()) << joined(desc.warnings);
  EXPECT_TRUE(find_material(desc, "checks")->textured);
  EXPECT_EQ(find_material(desc, "wood")->bsdf->name(), "two_sided(rough_plastic)");
  EXPECT_TRUE(find_material(desc, "metal")->bump);
  EXPECT_TRUE(find_material(desc, "leaf")->opacity);
  EXPECT_EQ(find_material(desc, "frosted")->bsdf->name(), "rough_dielectric");
  EXPECT_EQ(find_material(desc, "pane")->bsdf->name(), "thin_dielectric");
  EXPECT_EQ(find_material(desc, "gold")->bsdf->name(), "two_sided(conductor)");
  const auto scene = Scene::build(std::move(desc));
  EXPECT_TRUE(scene->warnings().empty()) << joined(scene->warnings());
}

}  // namespace

// Mitsuba's bitmap `gamma` is -1 (sRGB) or an exponent; another negative value is no curve
// and is refused by name, not read as some other curve.
TEST(TextureLoader, BitmapGammaThatIsNoCurveIsAnError) {
  const auto dir = test::scratch_dir("texture-loader-gamma");
  write_test_images(dir);
  const std::string path = write_file(dir, "scene.xml", R"(<scene version="0.6.0">
  <shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance">
    <string name="filename" value="checker.png"/><float name="gamma" value="-2"/></texture></bsdf>
    <emitter type="area"><spectrum name="radiance" value="1"/></emitter></shape>
</scene>)");
  try {
    load_scene_description(path);
    ADD_FAILURE() << "gamma -2 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bitmap gamma -2"), std::string::npos) << e.what();
  }
}
