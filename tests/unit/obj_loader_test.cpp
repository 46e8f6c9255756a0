// The OBJ reader: polygons fanned into triangles, normals read, transformed and computed, and
// non-finite coordinates kept whatever the line endings.
#include "emlt/scene/loaders/obj_loader.h"

#include <gtest/gtest.h>

#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::write_file;

}  // namespace

TEST(ObjLoader, FansPolygonsAndHandlesNormals) {
  const auto dir = test::scratch_dir("obj");
  // A unit quad in z = 0 plus a triangle with explicit (tilted) normals.
  const std::string path = write_file(dir, "mesh.obj",
                                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                      "vn 0 0 1\nvn 0.6 0 0.8\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                      "f 1/1/1 2/2/1 3/3/2 4/4/1\n");
  const MeshDesc flat = load_obj_mesh(path, Mat4(1.0f), false);
  EXPECT_EQ(flat.indices.size(), 6u);
  EXPECT_TRUE(flat.normals.empty());
  EXPECT_EQ(flat.uvs.size(), flat.positions.size());

  const Mat4 stretch =
      glm::mat4(Vec4(2, 0, 0, 0), Vec4(0, 1, 0, 0), Vec4(0, 0, 1, 0), Vec4(0, 0, 0, 1));
  const MeshDesc smooth = load_obj_mesh(path, stretch, true);
  ASSERT_EQ(smooth.normals.size(), smooth.positions.size());
  bool found_tilted = false;
  for (size_t i = 0; i < smooth.positions.size(); ++i) {
    EXPECT_NEAR(glm::length(smooth.normals[i]), 1.0f, 1e-5f);
    if (smooth.positions[i] == Vec3(2, 1, 0)) {
      // Inverse transpose of the stretch halves the x component before normalising.
      const Vec3 expected = glm::normalize(Vec3(0.3f, 0.0f, 0.8f));
      EXPECT_NEAR(smooth.normals[i].x, expected.x, 1e-5f);
      found_tilted = true;
    }
  }
  EXPECT_TRUE(found_tilted);

  // Without normals in the file, smooth normals are computed (angle weighted, so the ridge
  // of this symmetric tent points straight along y whatever the fan triangulation).
  const std::string tent = write_file(dir, "tent.obj",
                                      "v -1 0 0\nv 0 1 0\nv 0 1 1\nv -1 0 1\nv 1 0 0\nv 1 0 1\n"
                                      "f 1 2 3 4\nf 2 5 6 3\n");
  const MeshDesc computed = load_obj_mesh(tent, Mat4(1.0f), true);
  ASSERT_EQ(computed.normals.size(), computed.positions.size());
  int ridge_vertices = 0;
  for (size_t i = 0; i < computed.positions.size(); ++i) {
    if (computed.positions[i].y != 1.0f) continue;
    ++ridge_vertices;
    EXPECT_NEAR(std::abs(computed.normals[i].y), 1.0f, 1e-5f);
  }
  EXPECT_EQ(ridge_vertices, 2);
}

TEST(ObjLoader, PutsBackNonFiniteCoordinatesWhateverTheLineEndings) {
  // tinyobjloader reads "nan", "inf" and overflowing numbers as 0; the loader's own scan of
  // the v/vn/vt lines puts them back. CRLF endings, tabs, a word glued to its newline and a
  // last line without one must split as a stream would split them.
  const auto dir = test::scratch_dir("obj-nonfinite");
  const std::string path =
      write_file(dir, "mesh.obj",
                 "# nan inf in a comment\r\n"
                 "v 0 0 0\r\nv\t1 0 nan\r\nv 1 1 0\nvt 0 0\nvt 1e999 1\n"
                 "vt 1 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/3/1\nv 0 -INF 2");
  const MeshDesc mesh = load_obj_mesh(path, Mat4(1.0f), false);
  // The transform spreads a non-finite coordinate over the whole position.
  int non_finite_positions = 0, infinite_u = 0;
  for (const Vec3& p : mesh.positions) non_finite_positions += !std::isfinite(p.x + p.y + p.z);
  for (const Vec2& uv : mesh.uvs) infinite_u += std::isinf(uv.x) && uv.x > 0.0f;
  EXPECT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(non_finite_positions, 2);  // "nan" on the tabbed CRLF line, "-INF" on the last
  EXPECT_EQ(infinite_u, 1);            // 1e999 overflows
}
