// Mesh formats and shapes of Mitsuba 0.6 scenes beyond OBJ: serialized meshes (written
// here with zlib), the cylinder, and shapegroup/instance. Each file is loaded through a
// small XML scene; malformed files must give one line naming the file.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>

#include "emlt/core/error.h"
#include "emlt/scene/loaders/load_prefetch.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/loaders/ply_loader.h"
#include "emlt/scene/loaders/serialized_loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::write_file;

std::string xml_scene(const std::string& body) {
  return "<?xml version=\"1.0\"?>\n<scene version=\"0.6.0\">\n" + body + "\n</scene>\n";
}

SceneDescription load_xml(const std::filesystem::path& dir, const std::string& body) {
  return load_scene_description(write_file(dir, "scene.xml", xml_scene(body)));
}

using test::error_of;

bool any_contains(const std::vector<std::string>& lines, const std::string& needle) {
  for (const std::string& line : lines)
    if (line.find(needle) != std::string::npos) return true;
  return false;
}

void expect_vec3(const Vec3& actual, const Vec3& expected, float tolerance = 1e-6f) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

// --- Mitsuba .serialized writer --------------------------------------------------------

std::string le(uint64_t value, int bytes) {
  std::string out;
  for (int i = 0; i < bytes; ++i) out += char((value >> (8 * i)) & 0xFF);
  return out;
}

std::string le_real(double value, bool double_precision) {
  if (double_precision) {
    uint64_t bits;
    std::memcpy(&bits, &value, 8);
    return le(bits, 8);
  }
  const auto f = float(value);
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  return le(bits, 4);
}

struct TestMesh {
  std::vector<double> positions, normals, uvs, colors;  // flat, per vertex
  std::vector<uint32_t> indices;
  std::string name = "mesh";
  // Counts written to the header, when they should lie.
  int64_t claimed_vertices = -1, claimed_triangles = -1;
};

// A unit quad in z = 0 with two triangles (counter-clockwise seen from +z).
TestMesh quad() {
  TestMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

constexpr uint32_t kNormals = 0x1, kUvs = 0x2, kColors = 0x8, kSingle = 0x1000, kDouble = 0x2000;

// One mesh: the 4-byte header, then the zlib stream.
std::string serialized_mesh(const TestMesh& m, int version, bool double_precision) {
  uint32_t flags = double_precision ? kDouble : kSingle;
  if (!m.normals.empty()) flags |= kNormals;
  if (!m.uvs.empty()) flags |= kUvs;
  if (!m.colors.empty()) flags |= kColors;
  std::string raw = le(flags, 4);
  if (version == 4) raw += m.name + '\0';
  const uint64_t vertices = m.positions.size() / 3, triangles = m.indices.size() / 3;
  raw += le(m.claimed_vertices >= 0 ? uint64_t(m.claimed_vertices) : vertices, 8);
  raw += le(m.claimed_triangles >= 0 ? uint64_t(m.claimed_triangles) : triangles, 8);
  for (const auto* values : {&m.positions, &m.normals, &m.uvs, &m.colors})
    for (double v : *values) raw += le_real(v, double_precision);
  for (uint32_t i : m.indices) raw += le(i, 4);

  uLongf size = compressBound(uLong(raw.size()));
  std::string compressed(size, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(compressed.data()), &size,
                      reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), 9),
            Z_OK);
  compressed.resize(size);
  return le(0x041C, 2) + le(uint64_t(version), 2) + compressed;
}

// Meshes one after the other, then the offset dictionary Mitsuba's exporter writes.
std::string serialized_file(const std::vector<TestMesh>& meshes, int version,
                            bool double_precision = false) {
  std::string file, dictionary;
  for (const TestMesh& m : meshes) {
    dictionary += le(file.size(), version == 4 ? 8 : 4);
    file += serialized_mesh(m, version, double_precision);
  }
  return file + dictionary + le(meshes.size(), 4);
}

std::string serialized_shape(const std::string& file, const std::string& extra = "") {
  return "<shape type=\"serialized\"><string name=\"filename\" value=\"" + file + "\"/>" + extra +
         "</shape>";
}

}  // namespace

TEST(MeshFormatsSerialized, V3SinglePrecisionPositionsOnly) {
  const auto dir = test::scratch_dir("serialized-v3");
  write_file(dir, "quad.serialized", serialized_file({quad()}, 3));
  const SceneDescription desc =
      load_xml(dir, serialized_shape("quad.serialized",
                                     "<transform name=\"toWorld\"><scale value=\"2\"/>"
                                     "<translate x=\"1\" y=\"2\" z=\"3\"/></transform>"));
  ASSERT_EQ(desc.meshes.size(), 1u);
  const MeshDesc& mesh = desc.meshes[0];
  ASSERT_EQ(mesh.positions.size(), 4u);
  expect_vec3(mesh.positions[0], Vec3(1, 2, 3));
  expect_vec3(mesh.positions[1], Vec3(3, 2, 3));
  expect_vec3(mesh.positions[2], Vec3(3, 4, 3));
  expect_vec3(mesh.positions[3], Vec3(1, 4, 3));
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_TRUE(mesh.uvs.empty());
  // No normals in the file: Mitsuba computes smooth ones (here all +z).
  ASSERT_EQ(mesh.normals.size(), 4u);
  for (const Vec3& n : mesh.normals) expect_vec3(n, Vec3(0, 0, 1));
  EXPECT_NE(mesh.name.find("quad.serialized"), std::string::npos);
  EXPECT_FALSE(any_contains(desc.warnings, "line 3")) << desc.warnings.front();
}

TEST(MeshFormatsSerialized, V4DoublePrecisionWithNormalsUvsAndColours) {
  const auto dir = test::scratch_dir("serialized-v4");
  TestMesh m = quad();
  const double s = std::sqrt(0.5);
  m.normals = {0, 0, 1, s, 0, s, 0, s, s, 0, 0, 1};
  m.uvs = {0, 0, 0.25, 0, 0.25, 0.75, 0, 0.75};
  m.colors = {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
  m.positions[9] = 0.123456789012345;  // only double precision keeps all of it
  write_file(dir, "quad.serialized", serialized_file({m}, 4, true));
  // Non-uniform scale: normals go by the inverse transpose, then are normalised.
  const SceneDescription desc =
      load_xml(dir, serialized_shape("quad.serialized",
                                     "<transform name=\"toWorld\"><scale x=\"2\" y=\"1\" z=\"1\"/>"
                                     "</transform>"));
  ASSERT_EQ(desc.meshes.size(), 1u);
  const MeshDesc& mesh = desc.meshes[0];
  ASSERT_EQ(mesh.positions.size(), 4u);
  expect_vec3(mesh.positions[2], Vec3(2, 1, 0));
  EXPECT_EQ(mesh.positions[3].x, float(2 * 0.123456789012345));
  ASSERT_EQ(mesh.normals.size(), 4u);
  expect_vec3(mesh.normals[0], Vec3(0, 0, 1));
  expect_vec3(mesh.normals[1], glm::normalize(Vec3(0.5f, 0, 1)));
  expect_vec3(mesh.normals[2], Vec3(0, float(s), float(s)));
  // Texture coordinates are kept as stored (no flip, unlike OBJ).
  ASSERT_EQ(mesh.uvs.size(), 4u);
  EXPECT_EQ(mesh.uvs[2], Vec2(0.25f, 0.75f));
  EXPECT_EQ(mesh.uvs[3], Vec2(0.0f, 0.75f));
  // Colours are kept as stored, linear (Mitsuba's serialized format has no sRGB switch).
  ASSERT_EQ(mesh.colors.size(), 4u);
  EXPECT_EQ(mesh.colors[1], Rgb(0, 1, 0));
  EXPECT_EQ(mesh.colors[3], Rgb(1, 1, 1));
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(MeshFormatsSerialized, ShapeIndexSelectsAMeshInBothVersions) {
  const auto dir = test::scratch_dir("serialized-index");
  TestMesh triangle;
  triangle.positions = {5, 0, 0, 6, 0, 0, 5, 1, 0};
  triangle.indices = {0, 1, 2};
  triangle.name = "second";
  for (const int version : {3, 4}) {
    for (const bool dbl : {false, true}) {
      const std::string name =
          "two-v" + std::to_string(version) + (dbl ? "d" : "s") + ".serialized";
      write_file(dir, name, serialized_file({quad(), triangle}, version, dbl));
      const SceneDescription desc =
          load_xml(dir, serialized_shape(name, "<integer name=\"shapeIndex\" value=\"1\"/>") +
                            serialized_shape(name));
      ASSERT_EQ(desc.meshes.size(), 2u) << name;
      ASSERT_EQ(desc.meshes[0].positions.size(), 3u) << name;
      expect_vec3(desc.meshes[0].positions[1], Vec3(6, 0, 0));
      EXPECT_EQ(desc.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
      EXPECT_EQ(desc.meshes[1].positions.size(), 4u) << name;
      EXPECT_EQ(desc.meshes[1].indices.size(), 6u) << name;
    }
  }
}

TEST(MeshFormatsSerialized, NormalOptionsFollowMitsuba) {
  const auto dir = test::scratch_dir("serialized-normals");
  TestMesh m = quad();
  m.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  write_file(dir, "quad.serialized", serialized_file({m}, 4));
  const std::string face = "<boolean name=\"faceNormals\" value=\"true\"/>";
  const std::string flip = "<boolean name=\"flipNormals\" value=\"true\"/>";
  const SceneDescription desc = load_xml(
      dir, serialized_shape("quad.serialized", face) + serialized_shape("quad.serialized", flip) +
               serialized_shape("quad.serialized", face + flip) +
               serialized_shape("quad.serialized",
                                "<transform name=\"toWorld\"><scale x=\"-1\"/>"
                                "</transform>"));
  ASSERT_EQ(desc.meshes.size(), 4u);
  // faceNormals: flat shading, winding as stored.
  EXPECT_TRUE(desc.meshes[0].normals.empty());
  EXPECT_EQ(desc.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  // flipNormals with vertex normals: the normals turn, the winding stays.
  ASSERT_EQ(desc.meshes[1].normals.size(), 4u);
  for (const Vec3& n : desc.meshes[1].normals) expect_vec3(n, Vec3(0, 0, -1));
  EXPECT_EQ(desc.meshes[1].indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  // flipNormals with faceNormals: the winding turns.
  EXPECT_TRUE(desc.meshes[2].normals.empty());
  EXPECT_EQ(desc.meshes[2].indices, (std::vector<uint32_t>{0, 2, 1, 0, 3, 2}));
  // A mirroring toWorld reverses the winding, so the facing (+z) is kept.
  const MeshDesc& mirrored = desc.meshes[3];
  const Vec3 geometric =
      glm::cross(mirrored.positions[mirrored.indices[1]] - mirrored.positions[mirrored.indices[0]],
                 mirrored.positions[mirrored.indices[2]] - mirrored.positions[mirrored.indices[0]]);
  EXPECT_GT(geometric.z, 0.0f);
  for (const Vec3& n : mirrored.normals) expect_vec3(n, Vec3(0, 0, 1));
}

TEST(MeshFormatsSerialized, MaxSmoothAngleSplitsCreases) {
  const auto dir = test::scratch_dir("serialized-crease");
  // Two triangles sharing the edge (0,0,0)-(0,1,0), folded by 90 degrees.
  TestMesh m;
  m.positions = {0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1};
  m.indices = {0, 2, 1, 0, 1, 3};
  write_file(dir, "fold.serialized", serialized_file({m}, 4));
  const SceneDescription desc = load_xml(
      dir,
      serialized_shape("fold.serialized", "<float name=\"maxSmoothAngle\" value=\"30\"/>") +
          serialized_shape("fold.serialized", "<float name=\"maxSmoothAngle\" value=\"100\"/>") +
          serialized_shape("fold.serialized"));
  ASSERT_EQ(desc.meshes.size(), 3u);
  // Below the fold angle the shared vertices are split: each face keeps its own normal.
  const MeshDesc& split = desc.meshes[0];
  EXPECT_EQ(split.positions.size(), 6u);
  ASSERT_EQ(split.indices.size(), 6u);
  for (int k = 0; k < 3; ++k) {
    expect_vec3(split.normals[split.indices[k]], Vec3(0, 0, 1));
    expect_vec3(split.normals[split.indices[3 + k]], Vec3(1, 0, 0));
  }
  // Above it they stay shared and the shared edge's normals are averaged.
  const MeshDesc& merged = desc.meshes[1];
  EXPECT_EQ(merged.positions.size(), 4u);
  const Vec3 average = glm::normalize(Vec3(1, 0, 1));
  expect_vec3(merged.normals[merged.indices[0]], average);
  expect_vec3(merged.normals[merged.indices[2]], average);
  EXPECT_EQ(desc.meshes[2].positions.size(), 4u);
  EXPECT_EQ(error_of([&] {
              load_xml(dir, serialized_shape("fold.serialized",
                                             "<float name=\"maxSmoothAngle\" value=\"30\"/>"
                                             "<boolean name=\"faceNormals\" value=\"true\"/>"));
            }).find("cannot be given together") != std::string::npos,
            true);
}

TEST(MeshFormatsSerialized, RealExporterLayoutWithoutDictionaryIsOneMesh) {
  // A single mesh without an offset dictionary (the last four bytes are the zlib
  // checksum, a count the file cannot hold) is read from offset 0.
  const auto dir = test::scratch_dir("serialized-nodict");
  write_file(dir, "bare.serialized", serialized_mesh(quad(), 3, false));
  const SceneDescription desc = load_xml(dir, serialized_shape("bare.serialized"));
  ASSERT_EQ(desc.meshes.size(), 1u);
  EXPECT_EQ(desc.meshes[0].indices.size(), 6u);
}

TEST(MeshFormatsSerialized, MalformedFilesGiveOneLineNamingTheFile) {
  const auto dir = test::scratch_dir("serialized-bad");
  const std::string good = serialized_file({quad()}, 4);
  TestMesh out_of_range = quad();
  out_of_range.indices[4] = 4;
  TestMesh huge = quad();
  huge.claimed_triangles = 1000000000000;
  TestMesh many_vertices = quad();
  many_vertices.claimed_vertices = 1000000000000;
  std::string bad_magic = good, bad_version = good, bad_zlib = good;
  bad_magic[0] = 'X';
  bad_version[2] = 9;
  bad_zlib[5] = char(bad_zlib[5] ^ 0x5A);  // zlib header check byte
  std::string bad_checksum = good;
  // The Adler-32 checksum sits just before the dictionary (8 + 4 bytes).
  bad_checksum[good.size() - 13] = char(bad_checksum[good.size() - 13] ^ 0x01);

  const std::vector<std::pair<std::string, std::string>> cases = {
      {good.substr(0, good.size() / 2), "truncated"},
      {bad_magic, "not a Mitsuba serialized mesh"},
      {bad_version, "unsupported serialized format version 9"},
      {bad_zlib, "corrupt compressed data"},
      {bad_checksum, "corrupt compressed data"},
      {serialized_file({huge}, 4), "more than the file"},
      {serialized_file({many_vertices}, 3), "more than the file"},
      {serialized_file({out_of_range}, 4), "uses vertex 4, out of range (4 vertices)"},
      {std::string("\x1C\x04", 2), "too short"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string name = "bad" + std::to_string(i) + ".serialized";
    const std::string path = write_file(dir, name, cases[i].first);
    const std::string message = error_of([&] { load_xml(dir, serialized_shape(name)); });
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(cases[i].second), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }

  write_file(dir, "good.serialized", good);
  const std::string index_error = error_of([&] {
    load_xml(dir,
             serialized_shape("good.serialized", "<integer name=\"shapeIndex\" value=\"1\"/>"));
  });
  EXPECT_NE(index_error.find("good.serialized: shapeIndex 1 out of range (the file holds 1 mesh)"),
            std::string::npos)
      << index_error;
  const std::string missing =
      error_of([&] { load_xml(dir, serialized_shape("missing.serialized")); });
  EXPECT_NE(missing.find("missing.serialized: serialized mesh file not found"), std::string::npos)
      << missing;
}

TEST(MeshFormatsSerialized, MissingFilenameIsAnError) {
  const auto dir = test::scratch_dir("serialized-nofile");
  EXPECT_NE(
      error_of([&] { load_xml(dir, "<shape type=\"serialized\"/>"); }).find("needs a 'filename'"),
      std::string::npos);
}

// --- Cylinder ------------------------------------------------------------------------

namespace {

double mesh_area(const MeshDesc& mesh) {
  double area = 0.0;
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const Vec3 a = mesh.positions[mesh.indices[i]], b = mesh.positions[mesh.indices[i + 1]],
               c = mesh.positions[mesh.indices[i + 2]];
    area += 0.5 * double(glm::length(glm::cross(b - a, c - a)));
  }
  return area;
}

}  // namespace

TEST(MeshFormatsCylinder, AreaNormalsAndUvsMatchMitsuba) {
  const auto dir = test::scratch_dir("cylinder");
  const SceneDescription desc = load_xml(
      dir,
      "<shape type=\"cylinder\"><point name=\"p0\" x=\"1\" y=\"2\" z=\"3\"/>"
      "<point name=\"p1\" x=\"1\" y=\"5\" z=\"7\"/><float name=\"radius\" value=\"0.5\"/></shape>"
      "<shape type=\"cylinder\"><boolean name=\"flipNormals\" value=\"true\"/>"
      "<transform name=\"toWorld\"><scale value=\"2\"/></transform></shape>");
  ASSERT_EQ(desc.meshes.size(), 2u);
  const MeshDesc& mesh = desc.meshes[0];
  const Vec3 p0(1, 2, 3), axis = glm::normalize(Vec3(0, 3, 4));
  const double length = 5.0, radius = 0.5;
  // The rim is pushed out so that the area is exact (64 plain segments would miss by 0.04%).
  EXPECT_NEAR(mesh_area(mesh), 2.0 * M_PI * radius * length, 2.0 * M_PI * radius * length * 1e-5);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  ASSERT_EQ(mesh.uvs.size(), mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3 d = mesh.positions[v] - p0;
    const float along = glm::dot(d, axis);
    const Vec3 radial = d - along * axis;
    // v runs from 0 at p0 to 1 at p1; normals are radial and outward.
    EXPECT_NEAR(mesh.uvs[v].y, along / length, 1e-5);
    EXPECT_NEAR(glm::dot(mesh.normals[v], axis), 0.0f, 1e-5);
    EXPECT_NEAR(glm::dot(mesh.normals[v], glm::normalize(radial)), 1.0f, 1e-5);
    EXPECT_GE(mesh.uvs[v].x, 0.0f);
    EXPECT_LE(mesh.uvs[v].x, 1.0f);
  }
  // Each triangle's winding agrees with its vertex normals.
  for (size_t i = 0; i < mesh.indices.size(); i += 3) {
    const Vec3 a = mesh.positions[mesh.indices[i]];
    const Vec3 n = glm::cross(mesh.positions[mesh.indices[i + 1]] - a,
                              mesh.positions[mesh.indices[i + 2]] - a);
    EXPECT_GT(glm::dot(n, mesh.normals[mesh.indices[i]]), 0.0f);
  }

  // Default cylinder (p0 = 0, p1 = +z, radius 1) scaled by 2 and flipped: normals inward,
  // v = z / 2, and u = atan2(y, x) / 2pi, since Mitsuba's frame for the +z axis has its
  // first axis along +x (the seam's copies carry u = 1 instead of 0).
  const MeshDesc& flipped = desc.meshes[1];
  EXPECT_NEAR(mesh_area(flipped), 2.0 * M_PI * 2.0 * 2.0, 2.0 * M_PI * 4.0 * 1e-5);
  for (size_t v = 0; v < flipped.positions.size(); ++v) {
    const Vec3 p = flipped.positions[v];
    EXPECT_NEAR(flipped.uvs[v].y, p.z / 2.0f, 1e-5);
    EXPECT_NEAR(glm::dot(flipped.normals[v], glm::normalize(Vec3(p.x, p.y, 0))), -1.0f, 1e-5);
    const double u = std::atan2(double(p.y), double(p.x)) / (2.0 * M_PI);
    const double expected = u < 0.0 ? u + 1.0 : u;
    const double diff = std::abs(double(flipped.uvs[v].x) - expected);
    EXPECT_LT(std::min(diff, std::abs(diff - 1.0)), 1e-5) << v;
  }
}

TEST(MeshFormatsCylinder, DegenerateParametersAreErrors) {
  const auto dir = test::scratch_dir("cylinder-bad");
  EXPECT_NE(error_of([&] {
              load_xml(dir,
                       "<shape type=\"cylinder\"><float name=\"radius\" value=\"0\"/></shape>");
            }).find("'radius' must be a positive number (got 0)"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              load_xml(dir,
                       "<shape type=\"cylinder\"><point name=\"p1\" x=\"0\" y=\"0\" z=\"0\"/>"
                       "</shape>");
            }).find("p0 and p1"),
            std::string::npos);
}

// --- shapegroup / instance -----------------------------------------------------------

TEST(MeshFormatsInstance, InstancesCopyTheGroupIntoWorldSpace) {
  const auto dir = test::scratch_dir("instance");
  TestMesh m = quad();
  m.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  write_file(dir, "quad.serialized", serialized_file({m}, 4));
  const SceneDescription desc = load_xml(dir, R"(
  <shape type="instance"><ref id="group"/>
    <transform name="toWorld"><translate x="10"/></transform></shape>
  <shape type="shapegroup" id="group">
    <shape type="serialized"><string name="filename" value="quad.serialized"/>
      <bsdf type="diffuse"/></shape>
    <shape type="rectangle"/>
  </shape>
  <shape type="instance"><ref id="group"/>
    <transform name="toWorld"><scale x="1" y="1" z="-2"/><translate y="5"/></transform></shape>
  )");
  // The group alone adds nothing; each instance adds both of its shapes.
  ASSERT_EQ(desc.meshes.size(), 4u);
  const MeshDesc& first = desc.meshes[0];
  expect_vec3(first.positions[2], Vec3(11, 1, 0));
  EXPECT_GE(first.material, 0);
  EXPECT_NE(first.name.find("instance at line"), std::string::npos);
  expect_vec3(desc.meshes[1].positions[0], Vec3(9, -1, 0));

  // A mirroring instance transform: normals by the inverse transpose (here -z), and the
  // winding reversed so the facing agrees with them.
  const MeshDesc& mirrored = desc.meshes[2];
  expect_vec3(mirrored.positions[2], Vec3(1, 6, 0));
  for (const Vec3& n : mirrored.normals) expect_vec3(n, Vec3(0, 0, -1));
  const Vec3 a = mirrored.positions[mirrored.indices[0]];
  const Vec3 geometric = glm::cross(mirrored.positions[mirrored.indices[1]] - a,
                                    mirrored.positions[mirrored.indices[2]] - a);
  EXPECT_LT(geometric.z, 0.0f);
  const MeshDesc& rectangle = desc.meshes[3];
  const Vec3 r = rectangle.positions[rectangle.indices[0]];
  EXPECT_LT(glm::cross(rectangle.positions[rectangle.indices[1]] - r,
                       rectangle.positions[rectangle.indices[2]] - r)
                .z,
            0.0f);
}

TEST(MeshFormatsInstance, GroupAloneRendersNothingAndBadReferencesFail) {
  const auto dir = test::scratch_dir("instance-bad");
  const SceneDescription alone =
      load_xml(dir,
               "<shape type=\"shapegroup\" id=\"g\"><shape type=\"rectangle\"/></shape>"
               "<shape type=\"cube\"/>");
  EXPECT_EQ(alone.meshes.size(), 1u);
  EXPECT_NE(error_of([&] {
              load_xml(dir, "<shape type=\"instance\"><ref id=\"nothing\"/></shape>");
            }).find("not a shapegroup"),
            std::string::npos);
  EXPECT_NE(error_of([&] { load_xml(dir, "<shape type=\"instance\"/>"); }).find("needs a <ref"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              load_xml(dir,
                       "<shape type=\"shapegroup\" id=\"g\"><shape type=\"rectangle\">"
                       "<emitter type=\"area\"/></shape></shape>");
            }).find("emitter inside a shapegroup"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              load_xml(dir,
                       "<shape type=\"shapegroup\" id=\"g\"><shape type=\"instance\">"
                       "<ref id=\"g\"/></shape></shape>");
            }).find("nested instancing"),
            std::string::npos);
}

// --- PLY -----------------------------------------------------------------------------

namespace {

// Binary PLY writer: values in the declared sizes, either byte order.
struct PlyBytes {
  bool big_endian = false;
  std::string data;
  void put(uint64_t bits, int size) {
    for (int i = 0; i < size; ++i)
      data += char((bits >> (8 * (big_endian ? size - 1 - i : i))) & 0xFF);
  }
  void f64(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, 8);
    put(bits, 8);
  }
  void f32(float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    put(bits, 4);
  }
};

// A unit square (quad) and a pentagon beside it, with double positions, float texture_u/v,
// an extra element before the faces and extra properties to skip.
std::string binary_ply(bool big_endian) {
  PlyBytes b;
  b.big_endian = big_endian;
  const double positions[9][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},   {0, 1, 0}, {2, 0, 0},
                                  {3, 0, 0}, {3, 1, 0}, {2.5, 2, 0}, {2, 1, 0}};
  for (int v = 0; v < 9; ++v) {
    for (double c : positions[v]) b.f64(c);
    b.put(uint64_t(v) * 3, 2);             // ushort quality (skipped)
    b.f32(float(positions[v][0]) / 4.0f);  // texture_u
    b.f32(float(positions[v][1]) / 2.0f);  // texture_v
  }
  // element edge 1: list uchar int vertex (skipped by type)
  b.put(2, 1);
  b.put(0, 4);
  b.put(1, 4);
  // faces: uint count, int indices, then a float per face (skipped)
  const std::vector<std::vector<uint32_t>> faces = {{0, 1, 2, 3}, {4, 5, 6, 7, 8}};
  for (const auto& face : faces) {
    b.put(face.size(), 4);
    for (uint32_t i : face) b.put(i, 4);
    b.f32(0.5f);
  }
  return std::string("ply\r\nformat ") +
         (big_endian ? "binary_big_endian" : "binary_little_endian") +
         " 1.0\r\ncomment written by the test\r\nelement vertex 9\r\nproperty double x\r\n"
         "property double y\r\nproperty double z\r\nproperty ushort quality\r\n"
         "property float texture_u\r\nproperty float texture_v\r\nelement edge 1\r\n"
         "property list uchar int vertex\r\nelement face 2\r\n"
         "property list uint int vertex_indices\r\nproperty float weight\r\nend_header\r\n" +
         b.data;
}

constexpr const char* kAsciiPly = R"(ply
format ascii 1.0
comment a quad and a triangle, normals and s/t texture coordinates
element vertex 5
property float x
property float y
property float z
property float nx
property float ny
property float nz
property float s
property float t
property uchar red
element face 2
property uchar flags
property list uchar uint vertex_index
end_header
0 0 0  0 0 1  0 0  255
1 0 0  0 0 1  1 0  0
1 1 0  0 0 1  1 1  0
0 1 0  0 0 1  0 1  0
2 0 0  0 0.6 0.8  0.5 0.25  7
1 4 0 1 2 3
0 3 1 4 2
)";

std::string ply_shape(const std::string& file, const std::string& extra = "") {
  return "<shape type=\"ply\"><string name=\"filename\" value=\"" + file + "\"/>" + extra +
         "</shape>";
}

}  // namespace

TEST(MeshFormatsPly, AsciiWithNormalsAndQuads) {
  const auto dir = test::scratch_dir("ply-ascii");
  write_file(dir, "mesh.ply", kAsciiPly);
  const SceneDescription desc = load_xml(
      dir, ply_shape("mesh.ply", "<transform name=\"toWorld\"><translate z=\"1\"/></transform>"));
  ASSERT_EQ(desc.meshes.size(), 1u);
  const MeshDesc& mesh = desc.meshes[0];
  ASSERT_EQ(mesh.positions.size(), 5u);
  expect_vec3(mesh.positions[2], Vec3(1, 1, 1));
  expect_vec3(mesh.positions[4], Vec3(2, 0, 1));
  // The quad is fanned from its first corner; the triangle follows.
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 1, 4, 2}));
  ASSERT_EQ(mesh.normals.size(), 5u);
  expect_vec3(mesh.normals[0], Vec3(0, 0, 1));
  expect_vec3(mesh.normals[4], Vec3(0, 0.6f, 0.8f));
  ASSERT_EQ(mesh.uvs.size(), 5u);
  EXPECT_EQ(mesh.uvs[2], Vec2(1, 1));
  EXPECT_EQ(mesh.uvs[4], Vec2(0.5f, 0.25f));
  EXPECT_FALSE(any_contains(desc.warnings, "mesh.ply"));
}

TEST(MeshFormatsPly, BinaryBothByteOrdersWithPolygonsAndSkippedProperties) {
  const auto dir = test::scratch_dir("ply-binary");
  write_file(dir, "le.ply", binary_ply(false));
  write_file(dir, "be.ply", binary_ply(true));
  const SceneDescription desc = load_xml(dir, ply_shape("le.ply") + ply_shape("be.ply"));
  ASSERT_EQ(desc.meshes.size(), 2u);
  for (const MeshDesc& mesh : desc.meshes) {
    ASSERT_EQ(mesh.positions.size(), 9u) << mesh.name;
    expect_vec3(mesh.positions[7], Vec3(2.5f, 2, 0));
    // Quad fanned into 2 triangles, the pentagon into 3.
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 4, 7, 8}))
        << mesh.name;
    ASSERT_EQ(mesh.uvs.size(), 9u);
    EXPECT_EQ(mesh.uvs[7], Vec2(2.5f / 4.0f, 1.0f));
    // No normals in the file: smooth ones are computed (flat here, +z).
    ASSERT_EQ(mesh.normals.size(), 9u);
    for (const Vec3& n : mesh.normals) expect_vec3(n, Vec3(0, 0, 1));
  }
}

TEST(MeshFormatsPly, MirroringKeepsTheWindingAsMitsubaDoes) {
  const auto dir = test::scratch_dir("ply-mirror");
  write_file(dir, "mesh.ply", kAsciiPly);
  const SceneDescription desc =
      load_xml(dir, ply_shape("mesh.ply",
                              "<boolean name=\"faceNormals\" value=\"true\"/>"
                              "<transform name=\"toWorld\"><scale z=\"-1\"/></transform>") +
                        ply_shape("mesh.ply",
                                  "<transform name=\"toWorld\"><scale z=\"-1\"/>"
                                  "</transform>"));
  ASSERT_EQ(desc.meshes.size(), 2u);
  EXPECT_TRUE(desc.meshes[0].normals.empty());
  EXPECT_EQ(desc.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 1, 4, 2}));
  // The file's normals go by the inverse transpose.
  expect_vec3(desc.meshes[1].normals[0], Vec3(0, 0, -1));
  expect_vec3(desc.meshes[1].normals[4], Vec3(0, 0.6f, -0.8f));
}

TEST(MeshFormatsPly, MalformedFilesGiveOneLineNamingTheFile) {
  const auto dir = test::scratch_dir("ply-bad");
  const std::string ascii = kAsciiPly;
  const std::string binary = binary_ply(false);
  auto replaced = [](std::string text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"plx\n" + ascii.substr(4), "not a PLY file"},
      {replaced(ascii, "format ascii", "format ebcdic"), "unknown format 'ebcdic'"},
      {replaced(ascii, "property float s\n", "property quaternion s\n"),
       "unknown property type 'quaternion'"},
      {ascii.substr(0, ascii.find("end_header")), "no 'end_header'"},
      {binary.substr(0, binary.size() - 7), "truncated data (face 1)"},
      {ascii.substr(0, ascii.size() - 8), "truncated data (face 1)"},
      {replaced(ascii, "0.5 0.25", "0.5 zero"), "cannot parse 'zero'"},
      {replaced(ascii, "element vertex 5", "element vertex 1000000000000"), "more than the file"},
      {replaced(binary, "element face 2", "element face 4000000000"), "more than the file"},
      {replaced(ascii, "3 1 4 2", "3 1 5 2"), "face 1 uses vertex 5, out of range (5 vertices)"},
      {replaced(ascii, "3 1 4 2", "3 1 -1 2"), "uses vertex -1"},
      {replaced(ascii, "property list uchar uint vertex_index", "property list uchar uint other"),
       "no face element"},
      {replaced(ascii, "property float y\n", ""), "lacks x, y or z"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string name = "bad" + std::to_string(i) + ".ply";
    const std::string path = write_file(dir, name, cases[i].first);
    const std::string message = error_of([&] { load_xml(dir, ply_shape(name)); });
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << i << ": " << message;
    EXPECT_NE(message.find(cases[i].second), std::string::npos) << i << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  const std::string missing = error_of([&] { load_xml(dir, ply_shape("missing.ply")); });
  EXPECT_NE(missing.find("missing.ply: PLY file not found"), std::string::npos) << missing;
}

// PLY and serialized meshes read ahead (load_prefetch.h) and then placed are the meshes the
// direct loads give, bit for bit: transform, normals, a mirroring transform's winding (kept
// by PLY, reversed by serialized, as Mitsuba does) and the PLY's warnings.
TEST(MeshFormatsPrefetch, ReadAheadAndPlacedIsTheDirectLoad) {
  const auto dir = test::scratch_dir("mesh-prefetch");
  const std::string ply = write_file(dir, "mesh.ply", std::string(kAsciiPly) + "");
  const std::string short_face = write_file(
      dir, "short.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n");
  TestMesh triangle;
  triangle.positions = {0, 0, 1, 2, 0, 1, 0, 3, 1};
  triangle.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
  triangle.indices = {0, 1, 2};
  const std::string serialized =
      write_file(dir, "two.serialized", serialized_file({quad(), triangle}, 4));
  const Mat4 mirror = glm::scale(glm::translate(Mat4(1.0f), Vec3(1, 2, 3)), Vec3(2, 1, -1));
  using File = LoadPrefetch::MeshFile;
  // Bit for bit (memcmp may not be given an empty vector's null data()).
  const auto same_bits = [](const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);
  };
  const auto same = [&](const MeshDesc& a, const MeshDesc& b) {
    ASSERT_FALSE(a.positions.empty());
    EXPECT_TRUE(same_bits(a.positions, b.positions));
    EXPECT_TRUE(same_bits(a.normals, b.normals));
    EXPECT_EQ(a.uvs, b.uvs);
    EXPECT_EQ(a.indices, b.indices);
  };
  {
    const LoadPrefetch prefetch({}, {},
                                {{File::Format::Ply, ply, 0},
                                 {File::Format::Ply, short_face, 0},
                                 {File::Format::Serialized, serialized, 1},
                                 {File::Format::Serialized, serialized, 0}});
    auto read = LoadPrefetch::mesh({File::Format::Ply, ply, 0});
    ASSERT_TRUE(read.has_value());
    std::vector<std::string> warnings;
    same(place_ply_mesh(std::move(*read), mirror, &warnings), load_ply_mesh(ply, mirror));
    EXPECT_TRUE(warnings.empty());
    read = LoadPrefetch::mesh({File::Format::Ply, short_face, 0});
    ASSERT_TRUE(read.has_value());
    std::vector<std::string> direct_warnings;
    same(place_ply_mesh(std::move(*read), mirror, &warnings),
         load_ply_mesh(short_face, mirror, &direct_warnings));
    EXPECT_EQ(warnings, direct_warnings);
    ASSERT_EQ(warnings.size(), 1u);
    for (const int index : {1, 0}) {
      read = LoadPrefetch::mesh({File::Format::Serialized, serialized, index});
      ASSERT_TRUE(read.has_value()) << index;
      EXPECT_TRUE(read->warnings.empty());
      const MeshDesc placed = place_serialized_mesh(std::move(read->mesh), mirror);
      same(placed, load_serialized_mesh(serialized, index, mirror));
      if (index == 0) {  // the quad's first triangle, reversed by the mirroring transform
        EXPECT_EQ(placed.indices, (std::vector<uint32_t>{0, 2, 1, 0, 3, 2}));
      }
    }
    // Taken once; another shape index is read directly.
    EXPECT_FALSE(LoadPrefetch::mesh({File::Format::Ply, ply, 0}).has_value());
    EXPECT_FALSE(LoadPrefetch::mesh({File::Format::Serialized, serialized, 2}).has_value());
  }
  // Through the Mitsuba loader, which announces both kinds: the same meshes.
  const SceneDescription desc = load_xml(
      dir, ply_shape("mesh.ply") +
               serialized_shape("two.serialized",
                                "<integer name=\"shapeIndex\" value=\"1\"/>"
                                "<transform name=\"toWorld\"><scale z=\"-1\"/></transform>"));
  ASSERT_EQ(desc.meshes.size(), 2u);
  EXPECT_EQ(desc.meshes[0].positions, load_ply_mesh(ply, Mat4(1.0f)).positions);
  EXPECT_EQ(desc.meshes[1].indices,
            load_serialized_mesh(serialized, 1, glm::scale(Mat4(1.0f), Vec3(1, 1, -1))).indices);
}
