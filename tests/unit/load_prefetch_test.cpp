// Files read ahead by a LoadPrefetch are the files the loader would have read itself: the
// same contents and the same errors, taken once each, and nothing for files not announced.
#include "emlt/scene/loaders/load_prefetch.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>

#include "emlt/core/error.h"
#include "emlt/image/image.h"
#include "emlt/scene/loaders/obj_loader.h"
#include "emlt/scene/shape_builders.h"
#include "support/test_support.h"

using namespace emlt;
namespace fs = std::filesystem;

using test::error_of;

TEST(LoadPrefetch, GivesWhatTheDirectReadsGiveOnceEach) {
  const fs::path dir = test::scratch_dir("prefetch");
  const std::string obj = (dir / "quad.obj").string(), png = (dir / "tex.png").string();
  std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                        "f 1/1 2/2 3/3 4/4\n";
  Image texture(5, 3);
  for (size_t i = 0; i < texture.pixels.size(); ++i) texture.pixels[i] = Rgb(float(i) / 15.0f);
  write_image(png, texture);
  const std::string missing = (dir / "missing.obj").string();

  const ObjInFileSpace direct = read_obj_file(obj, true, true);
  const StoredImage direct_image = read_stored_image(png);
  const std::string missing_error = error_of([&] { read_obj_file(missing, true, true); });
  {
    const LoadPrefetch prefetch({png}, {{obj, true, true}, {missing, true, true}});
    const auto image = LoadPrefetch::stored_image(png);
    ASSERT_TRUE(image.has_value());
    EXPECT_EQ(image->bytes, direct_image.bytes);
    EXPECT_EQ(image->width, 5);
    const auto mesh = LoadPrefetch::obj(obj, true, true);
    ASSERT_TRUE(mesh.has_value());
    ASSERT_EQ(mesh->mesh.positions.size(), direct.mesh.positions.size());
    EXPECT_EQ(0, std::memcmp(mesh->mesh.positions.data(), direct.mesh.positions.data(),
                             direct.mesh.positions.size() * sizeof(Vec3)));
    EXPECT_EQ(mesh->mesh.uvs, direct.mesh.uvs);
    EXPECT_EQ(mesh->mesh.indices, direct.mesh.indices);
    EXPECT_EQ(mesh->needs_smooth_normals, direct.needs_smooth_normals);
    // The error of a missing file is the direct read's, thrown where it is taken.
    EXPECT_EQ(error_of([] {
                LoadPrefetch::obj((test::scratch_dir("prefetch") / "missing.obj").string(), true,
                                  true);
              }),
              missing_error);
    EXPECT_NE(missing_error, "");
    // Taken once: a second request, other options or another file are read directly.
    EXPECT_FALSE(LoadPrefetch::stored_image(png).has_value());
    EXPECT_FALSE(LoadPrefetch::obj(obj, true, true).has_value());
    EXPECT_FALSE(LoadPrefetch::obj(obj, false, true).has_value());
    EXPECT_FALSE(LoadPrefetch::stored_image((dir / "other.png").string()).has_value());
  }
  EXPECT_FALSE(LoadPrefetch::stored_image(png).has_value());  // none active once it is gone
}

// A mesh read in the file's space and then placed is the mesh the file describes in the
// world: its positions transformed, and its smooth normals those of the world-space
// surface (under a non-uniform scale, normals computed before the placement would differ).
TEST(LoadPrefetch, PlacedObjHasTheWorldSpaceSmoothNormals) {
  const std::string obj = test::source_path("scenes/kitchen/meshes/kettle.obj");  // no vn
  const Mat4 to_world =
      glm::scale(glm::translate(Mat4(1.0f), Vec3(0.5f, -2.0f, 3.0f)), Vec3(3.0f, 1.0f, 0.25f));
  const ObjInFileSpace local = read_obj_file(obj, true, true);
  ASSERT_TRUE(local.needs_smooth_normals);
  const MeshDesc placed = place_obj_mesh(local, to_world, nullptr);
  MeshDesc expected = local.mesh;
  transform_mesh(expected, to_world, false);
  compute_smooth_normals(expected);
  ASSERT_EQ(placed.normals.size(), expected.normals.size());
  for (size_t i = 0; i < expected.normals.size(); ++i)
    ASSERT_LT(glm::length(placed.normals[i] - expected.normals[i]), 1e-6f) << i;
  const MeshDesc direct = load_obj_mesh(obj, to_world, true);
  EXPECT_EQ(0, std::memcmp(direct.normals.data(), placed.normals.data(),
                           direct.normals.size() * sizeof(Vec3)));
}
