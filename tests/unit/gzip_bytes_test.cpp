// gzip-compressed inputs (src/scene/loaders/gzip_bytes.h): zlib's own gzip output read back,
// concatenated members, data that is not gzip left as it is, damaged data as a one-line
// error naming the file; and pbrt-v4 scenes that include a `.pbrt.gz` text and a `.ply.gz`
// mesh, as the public hair, fur, ganesha and sssdragon scenes do.
#include "src/scene/loaders/gzip_bytes.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

// Writes `text` gzip-compressed to dir/name with zlib's gzip writer; returns the path.
std::string write_gzip(const std::filesystem::path& dir, const std::string& name,
                       const std::string& text) {
  const std::string path = (dir / name).string();
  gzFile file = gzopen(path.c_str(), "wb");
  EXPECT_NE(file, nullptr);
  EXPECT_EQ(gzwrite(file, text.data(), unsigned(text.size())), int(text.size()));
  gzclose(file);
  return path;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(Gzip, ReadsZlibsOutputAndConcatenatedMembers) {
  const auto dir = test::scratch_dir("gzip-members");
  const std::string first = read_bytes(write_gzip(dir, "a.gz", "first member\n"));
  const std::string second = read_bytes(write_gzip(dir, "b.gz", std::string(100000, 'x')));
  ASSERT_TRUE(loader::is_gzip(first));
  EXPECT_EQ(loader::gunzip("a.gz", first), "first member\n");
  EXPECT_EQ(loader::gunzip("ab.gz", first + second), "first member\n" + std::string(100000, 'x'));
  EXPECT_EQ(loader::maybe_gunzip("plain.pbrt", "WorldBegin\n"), "WorldBegin\n");
}

TEST(Gzip, DamagedDataIsAOneLineErrorNamingTheFile) {
  const auto dir = test::scratch_dir("gzip-damaged");
  const std::string good = read_bytes(write_gzip(dir, "a.gz", std::string(5000, 'y')));
  const auto error = [](const std::string& bytes, size_t limit = size_t(1) << 32) {
    return test::error_of([&] { loader::gunzip("m.ply.gz", bytes, limit); });
  };
  EXPECT_EQ(error(good.substr(0, good.size() / 2)), "m.ply.gz: truncated gzip data");
  std::string flipped = good;
  flipped[good.size() - 3] ^= 0x5a;  // inside the trailer's length: zlib's check fails
  EXPECT_NE(error(flipped).find("m.ply.gz: corrupt gzip data"), std::string::npos)
      << error(flipped);
  EXPECT_EQ(error(good + "junk"), "m.ply.gz: data after the end of the gzip stream");
  EXPECT_NE(error(read_bytes(write_gzip(dir, "big.gz", std::string(3 << 20, 'z'))), 1 << 20)
                .find("expands beyond 1 MiB"),
            std::string::npos);
}

// A pbrt-v4 scene that includes a gzip-compressed text and a gzip-compressed PLY mesh.
TEST(Gzip, PbrtScenesIncludeCompressedTextsAndPlyMeshes) {
  const auto dir = test::scratch_dir("gzip-pbrt");
  write_gzip(dir, "tri.pbrt.gz",
             "Shape \"trianglemesh\" \"point3 P\" [-1 -1 5  1 -1 5  0 1 5] "
             "\"integer indices\" [0 1 2]\n");
  write_gzip(dir, "mesh.ply.gz",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
             "end_header\n0 0 7\n1 0 7\n0 1 7\n3 0 1 2\n");
  const std::string head =
      "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 60\n"
      "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n";
  const SceneDescription desc = load_scene_description(test::write_file(
      dir, "scene.pbrt",
      head + "Include \"tri.pbrt.gz\"\nShape \"plymesh\" \"string filename\" \"mesh.ply.gz\"\n"));
  ASSERT_EQ(desc.meshes.size(), 2u);
  EXPECT_EQ(desc.meshes[0].positions[2], Vec3(0, 1, 5));
  EXPECT_EQ(desc.meshes[1].positions[1], Vec3(1, 0, 7));

  const std::string cut = read_bytes((dir / "mesh.ply.gz").string());
  test::write_file(dir, "cut.ply.gz", cut.substr(0, cut.size() / 2));
  const std::string error = test::error_of([&] {
    load_scene_description(test::write_file(
        dir, "cut.pbrt", head + "Shape \"plymesh\" \"string filename\" \"cut.ply.gz\"\n"));
  });
  EXPECT_NE(error.find("cut.ply.gz: truncated gzip data"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}
