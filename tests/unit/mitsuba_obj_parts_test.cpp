// Mitsuba 0.6 makes a separate mesh of each part of an OBJ file (split at a `g`, and at a
// `usemtl`, after faces) unless `collapse` is set; `shapeIndex` keeps the meshes Mitsuba
// creates for it; `maxSmoothAngle` splits vertices by angle; `loadMaterials` takes the
// materials of the file's library. The reader keeps the parts apart as Mitsuba does, the
// loader reads the four parameters (verdict exact) and reports a library Mitsuba would use.
#include <gtest/gtest.h>

#include <string>

#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/loaders/obj_loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

// Three parts sharing vertices 2 and 3: a `g`, a `usemtl` after faces, and a `g`.
const char* kParts = R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 2 1 0
g first
f 1 2 3
f 1 3 4
usemtl red
f 2 5 6
g third
f 2 6 3
)";

std::string scene_with_obj(const std::string& params, const std::string& body = "") {
  return R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
  <shape type="obj"><string name="filename" value="parts.obj"/>)" +
         params + body + R"(</shape>
</scene>
)";
}

}  // namespace

TEST(MitsubaObjParts, PartsShareNoVertexUnlessCollapsed) {
  const auto dir = test::scratch_dir("obj-parts");
  const std::string obj = test::write_file(dir, "parts.obj", kParts);
  const ObjInFileSpace apart = read_obj_file(obj, true, true);
  EXPECT_EQ(apart.triangle_parts, (std::vector<int>{0, 0, 1, 2}));
  EXPECT_EQ(apart.last_part, 2);
  // Part 0 has vertices 1-4, part 1 vertices 2, 5, 6, part 2 vertices 2, 6, 3.
  EXPECT_EQ(apart.mesh.positions.size(), 10u);
  const ObjInFileSpace merged = read_obj_file(obj, true, true, true);
  EXPECT_EQ(merged.triangle_parts, (std::vector<int>{0, 0, 0, 0}));
  EXPECT_EQ(merged.last_part, 0);
  EXPECT_EQ(merged.mesh.positions.size(), 6u);
  EXPECT_FALSE(apart.has_material_library);
}

TEST(MitsubaObjParts, ShapeIndexKeepsTheMeshesMitsubaCreatesForIt) {
  const auto dir = test::scratch_dir("obj-parts-index");
  const std::string obj = test::write_file(dir, "parts.obj", kParts);
  const auto triangles = [&](int shape_index) {
    ObjInFileSpace read = read_obj_file(obj, true, true);
    keep_obj_part(read, shape_index);
    EXPECT_EQ(read.mesh.indices.size(), 3 * read.triangle_parts.size());
    for (uint32_t index : read.mesh.indices) EXPECT_LT(index, read.mesh.positions.size());
    return read.triangle_parts;
  };
  EXPECT_EQ(triangles(-1), (std::vector<int>{0, 0, 1, 2}));
  EXPECT_EQ(triangles(0), (std::vector<int>{0, 0}));
  // Mitsuba creates the last part along with the one before it, and none for its own index.
  EXPECT_EQ(triangles(1), (std::vector<int>{1, 2}));
  EXPECT_TRUE(triangles(2).empty());
}

TEST(MitsubaObjParts, LoaderReadsTheParametersAsMitsubaDoes) {
  const auto dir = test::scratch_dir("obj-parts-loader");
  test::write_file(dir, "parts.obj", kParts);
  const SceneDescription one = load_scene_description(
      test::write_file(dir, "one.xml", scene_with_obj(R"(<integer name="shapeIndex" value="0"/>
        <boolean name="collapse" value="false"/><float name="maxSmoothAngle" value="30"/>)")));
  EXPECT_EQ(one.verdict(), "exact");
  ASSERT_EQ(one.meshes.size(), 2u);
  EXPECT_EQ(one.meshes.back().indices.size(), 6u);

  // An index past the meshes Mitsuba creates adds nothing, as in Mitsuba.
  const SceneDescription none = load_scene_description(test::write_file(
      dir, "none.xml", scene_with_obj(R"(<integer name="shapeIndex" value="2"/>)")));
  EXPECT_EQ(none.verdict(), "exact");
  EXPECT_EQ(none.meshes.size(), 1u);

  const std::string both =
      test::write_file(dir, "both.xml", scene_with_obj(R"(<float name="maxSmoothAngle" value="30"/>
        <boolean name="faceNormals" value="true"/>)"));
  EXPECT_NE(test::error_of([&] {
              load_scene_description(both);
            }).find("'maxSmoothAngle' and 'faceNormals' cannot be given together"),
            std::string::npos);
}

TEST(MitsubaObjParts, MaterialLibraryMitsubaWouldUseIsReported) {
  const auto dir = test::scratch_dir("obj-parts-mtl");
  test::write_file(dir, "parts.mtl", "newmtl red\nKd 0.8 0.1 0.1\n");
  test::write_file(dir, "parts.obj", std::string("mtllib parts.mtl\n") + kParts);
  const SceneDescription library =
      load_scene_description(test::write_file(dir, "library.xml", scene_with_obj("")));
  EXPECT_NE(library.verdict(), "exact");
  bool reported = false;
  for (const std::string& w : library.warnings)
    reported |= w.find("material library (mtllib) are not loaded") != std::string::npos;
  EXPECT_TRUE(reported);
  // A BSDF of the shape replaces the library's in Mitsuba too; so does loadMaterials false.
  EXPECT_EQ(load_scene_description(
                test::write_file(dir, "bsdf.xml", scene_with_obj("", R"(<bsdf type="diffuse"/>)")))
                .verdict(),
            "exact");
  EXPECT_EQ(
      load_scene_description(
          test::write_file(dir, "off.xml",
                           scene_with_obj(R"(<boolean name="loadMaterials" value="false"/>)")))
          .verdict(),
      "exact");
}
