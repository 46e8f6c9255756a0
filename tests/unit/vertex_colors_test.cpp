// Mitsuba 0.6's per-vertex colours: what its PLY reader takes from a file (property names,
// uchar / 255 and float as stored, the ply shape's `srgb` curve), and the `vertexcolors`
// texture reading them interpolated barycentrically at a hit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/loaders/ply_loader.h"
#include "emlt/scene/scene.h"
#include "emlt/scene/texture.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::write_file;

// One triangle, colours of every kind the reader must tell apart.
constexpr const char* kAsciiUchar = R"(ply
format ascii 1.0
element vertex 3
property float x
property float y
property float z
property uchar red
property uchar green
property uchar blue
element face 1
property list uchar int vertex_indices
end_header
0 0 0 255 0 0
1 0 0 0 128 0
0 1 0 0 0 51
3 0 1 2
)";

constexpr const char* kAsciiFloat = R"(ply
format ascii 1.0
element vertex 3
property float x
property float y
property float z
property float diffuse_red
property float diffuse_green
property float diffuse_blue
property uchar red
element face 1
property list uchar int vertex_indices
end_header
0 0 0 0.25 0.5 0.75 10
1 0 0 1.5 0 0 20
0 1 0 0 0 0.125 30
3 0 1 2
)";

// Binary little endian: float x y z, then uchar red, float green, uchar blue.
std::string binary_ply() {
  std::string data;
  auto f32 = [&](float v) {
    char bytes[4];
    std::memcpy(bytes, &v, 4);
    data.append(bytes, 4);
  };
  const float positions[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const unsigned char reds[3] = {0, 51, 255}, blues[3] = {255, 0, 102};
  const float greens[3] = {0.5f, 0.25f, 1.0f};
  for (int v = 0; v < 3; ++v) {
    for (float c : positions[v]) f32(c);
    data += char(reds[v]);
    f32(greens[v]);
    data += char(blues[v]);
  }
  data += char(3);
  for (int32_t i : {0, 1, 2}) {
    char bytes[4];
    std::memcpy(bytes, &i, 4);
    data.append(bytes, 4);
  }
  return "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nproperty uchar red\nproperty float green\n"
         "property uchar blue\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n" +
         data;
}

float srgb_decoded(float value) {
  return value <= 0.04045f ? value / 12.92f : std::pow((value + 0.055f) / 1.055f, 2.4f);
}

// A camera, a constant sky and whatever shapes `body` holds.
std::string xml_scene(const std::string& body) {
  return R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <transform name="toWorld"><lookat origin="0.3,0.3,5" target="0.3,0.3,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
  <emitter type="constant"/>
)" + body +
         "\n</scene>\n";
}

std::string ply_shape(const std::string& file, const std::string& extra = "") {
  return "<shape type=\"ply\"><string name=\"filename\" value=\"" + file + "\"/>" + extra +
         "<bsdf type=\"diffuse\"><texture type=\"vertexcolors\" name=\"reflectance\"/></bsdf>"
         "</shape>";
}

}  // namespace

TEST(VertexColors, AsciiUcharIsDividedBy255) {
  const auto dir = test::scratch_dir("vcolors-ascii-uchar");
  const MeshInFileSpace ply = read_ply_file(write_file(dir, "tri.ply", kAsciiUchar));
  ASSERT_EQ(ply.mesh.colors.size(), 3u);
  EXPECT_EQ(ply.mesh.colors[0], Rgb(1.0f, 0.0f, 0.0f));
  EXPECT_EQ(ply.mesh.colors[1], Rgb(0.0f, 128.0f / 255.0f, 0.0f));
  EXPECT_EQ(ply.mesh.colors[2], Rgb(0.0f, 0.0f, 51.0f / 255.0f));
  EXPECT_TRUE(ply.warnings.empty());
}

TEST(VertexColors, AsciiFloatAsStoredAndTheLaterPropertyOfAChannelWins) {
  const auto dir = test::scratch_dir("vcolors-ascii-float");
  const MeshInFileSpace ply = read_ply_file(write_file(dir, "tri.ply", kAsciiFloat));
  ASSERT_EQ(ply.mesh.colors.size(), 3u);
  // `red` (uchar) follows `diffuse_red` in the vertex: Mitsuba's reader sets red from both,
  // the later last.
  EXPECT_EQ(ply.mesh.colors[0], Rgb(10.0f / 255.0f, 0.5f, 0.75f));
  EXPECT_EQ(ply.mesh.colors[1], Rgb(20.0f / 255.0f, 0.0f, 0.0f));
  EXPECT_EQ(ply.mesh.colors[2], Rgb(30.0f / 255.0f, 0.0f, 0.125f));
}

TEST(VertexColors, BinaryMixesUcharAndFloatChannels) {
  const auto dir = test::scratch_dir("vcolors-binary");
  const MeshInFileSpace ply = read_ply_file(write_file(dir, "tri.ply", binary_ply()));
  ASSERT_EQ(ply.mesh.colors.size(), 3u);
  EXPECT_EQ(ply.mesh.colors[0], Rgb(0.0f, 0.5f, 1.0f));
  EXPECT_EQ(ply.mesh.colors[1], Rgb(51.0f / 255.0f, 0.25f, 0.0f));
  EXPECT_EQ(ply.mesh.colors[2], Rgb(1.0f, 1.0f, 102.0f / 255.0f));
}

TEST(VertexColors, OtherTypesAreIgnoredWithAWarning) {
  const auto dir = test::scratch_dir("vcolors-ushort");
  std::string text = kAsciiUchar;
  text.replace(text.find("uchar red"), 9, "ushort red");
  const MeshInFileSpace ply = read_ply_file(write_file(dir, "tri.ply", text));
  EXPECT_TRUE(ply.mesh.colors.empty());  // no red channel Mitsuba sees: no colours
  ASSERT_EQ(ply.warnings.size(), 1u);
  EXPECT_NE(ply.warnings[0].find("'red'"), std::string::npos) << ply.warnings[0];
}

TEST(VertexColors, SrgbByDefaultLinearOnRequest) {
  const auto dir = test::scratch_dir("vcolors-srgb");
  write_file(dir, "tri.ply", kAsciiUchar);
  const std::string xml = xml_scene(
      ply_shape("tri.ply") + ply_shape("tri.ply", "<boolean name=\"srgb\" value=\"false\"/>"));
  const SceneDescription desc = load_scene_description(write_file(dir, "scene.xml", xml));
  ASSERT_EQ(desc.meshes.size(), 2u);
  const float g = 128.0f / 255.0f, b = 51.0f / 255.0f;
  EXPECT_EQ(desc.meshes[0].colors[1], Rgb(0.0f, srgb_decoded(g), 0.0f));
  EXPECT_EQ(desc.meshes[0].colors[2], Rgb(0.0f, 0.0f, srgb_decoded(b)));
  EXPECT_NEAR(desc.meshes[0].colors[1].y, 0.2158605f, 1e-6f);
  EXPECT_EQ(desc.meshes[1].colors[1], Rgb(0.0f, g, 0.0f));
  EXPECT_TRUE(desc.warnings.empty());  // vertexcolors and srgb are both understood
}

TEST(VertexColors, TextureReadsTheColourInterpolatedAtTheHit) {
  const auto dir = test::scratch_dir("vcolors-hit");
  write_file(dir, "tri.ply", kAsciiUchar);
  const std::string xml =
      xml_scene(ply_shape("tri.ply", "<boolean name=\"srgb\" value=\"false\"/>"));
  const auto scene = Scene::build(load_scene_description(write_file(dir, "scene.xml", xml)));
  EXPECT_TRUE(scene->warnings().empty());
  SurfaceHit hit;
  // (0.25, 0.5): barycentrics 0.25, 0.25, 0.5 of vertices 0, 1, 2.
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.25f, 0.5f, 1.0f), Vec3(0, 0, -1)}, hit));
  const Rgb expected =
      0.25f * Rgb(1, 0, 0) + 0.25f * Rgb(0, 128.0f / 255.0f, 0) + 0.5f * Rgb(0, 0, 51.0f / 255.0f);
  EXPECT_NEAR(hit.vertex_color.x, expected.x, 1e-6f);
  EXPECT_NEAR(hit.vertex_color.y, expected.y, 1e-6f);
  EXPECT_NEAR(hit.vertex_color.z, expected.z, 1e-6f);
  // The diffuse reflectance is that colour: f = colour / pi.
  const Vec3 up(0, 0, 1);
  const Rgb f =
      hit.bsdf->eval(BsdfContext{hit.uv, TransportMode::Radiance, hit.vertex_color}, up, up);
  EXPECT_NEAR(f.x * kPi, expected.x, 1e-6f);
  EXPECT_NEAR(f.y * kPi, expected.y, 1e-6f);
  EXPECT_NEAR(f.z * kPi, expected.z, 1e-6f);
}

TEST(VertexColors, SurfaceWithoutColoursReadsBlackWithAWarning) {
  const auto dir = test::scratch_dir("vcolors-none");
  const std::string xml = xml_scene(
      "<shape type=\"rectangle\"><bsdf type=\"diffuse\">"
      "<texture type=\"vertexcolors\" name=\"reflectance\"/></bsdf></shape>");
  const auto scene = Scene::build(load_scene_description(write_file(dir, "scene.xml", xml)));
  ASSERT_EQ(scene->warnings().size(), 1u);
  EXPECT_NE(scene->warnings()[0].find("no vertex colours"), std::string::npos);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.25f, 0.5f, 1.0f), Vec3(0, 0, -1)}, hit));
  EXPECT_EQ(hit.vertex_color, Rgb(0.0f));
}

TEST(VertexColors, ScaleOfVertexColorsScalesTheColour) {
  const TexturePtr scaled = make_scale_texture(make_vertex_colors_texture(), Rgb(2.0f));
  EXPECT_TRUE(scaled->reads_vertex_colors());
  EXPECT_FALSE(scaled->constant());
  EXPECT_EQ(scaled->eval_at(Vec2(0.3f), Rgb(0.1f, 0.2f, 0.3f)), Rgb(0.2f, 0.4f, 0.6f));
  EXPECT_EQ(scaled->eval(Vec2(0.3f)), Rgb(0.0f));  // no surface point, no colour
}
