// Shapes and their transforms in either format, Mitsuba's transform elements as its parser
// reads them, and the BSDF Mitsuba gives a shape that names none.
#include <gtest/gtest.h>

#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"
#include "support/loader_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::load_and_build_error;
using test::small_json;
using test::small_xml;
using test::write_file;

}  // namespace

TEST(Loader, XmlAndJsonPrimitiveShapesAndTransformsAgree) {
  const auto dir = test::scratch_dir("shapes");
  const std::string json = write_file(dir, "shapes.json", small_json("", R"(,
    {"type": "cube", "transform": [{"scale": [1, 2, 3]}, {"rotate": {"axis": [0, 1, 0], "angle": 30}}, {"translate": [4, 0, 1]}]},
    {"type": "disk", "transform": [{"matrix": [2,0,0,1, 0,2,0,2, 0,0,2,3, 0,0,0,1]}]},
    {"type": "sphere", "center": [1, 1, 1], "radius": 0.5, "transform": [{"scale": 2}], "emission": [2, 2, 2]},
    {"type": "rectangle", "transform": [{"lookat": {"origin": [0, 3, 0], "target": [0, 0, 0], "up": [0, 0, 1]}}],
     "material": {"type": "roughconductor", "alpha": 0.2, "material": "Au"}})"));
  const std::string xml = write_file(dir, "shapes.xml", small_xml(R"(
  <shape type="cube"><transform name="toWorld"><scale x="1" y="2" z="3"/><rotate y="1" angle="30"/>
    <translate x="4" y="0" z="1"/></transform></shape>
  <shape type="disk"><transform name="toWorld"><matrix value="2 0 0 1  0 2 0 2  0 0 2 3  0 0 0 1"/></transform></shape>
  <shape type="sphere"><point name="center" x="1" y="1" z="1"/><float name="radius" value="0.5"/>
    <transform name="toWorld"><scale value="2"/></transform>
    <emitter type="area"><rgb name="radiance" value="2, 2, 2"/></emitter></shape>
  <shape type="rectangle"><transform name="toWorld"><lookat origin="0, 3, 0" target="0, 0, 0" up="0, 0, 1"/></transform>
    <bsdf type="twosided"><bsdf type="roughconductor"><float name="alpha" value="0.2"/>
      <string name="distribution" value="ggx"/><string name="material" value="Au"/></bsdf></bsdf></shape>)"));
  const SceneDescription a = load_scene_description(json), b = load_scene_description(xml);
  EXPECT_TRUE(a.warnings.empty()) << a.warnings.front();
  EXPECT_TRUE(b.warnings.empty()) << b.warnings.front();
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (size_t m = 0; m < a.meshes.size(); ++m) {
    ASSERT_EQ(a.meshes[m].positions.size(), b.meshes[m].positions.size());
    EXPECT_EQ(a.meshes[m].indices, b.meshes[m].indices);
    for (size_t i = 0; i < a.meshes[m].positions.size(); ++i)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a.meshes[m].positions[i][c], b.meshes[m].positions[i][c], 1e-5f);
  }
  ASSERT_EQ(a.spheres.size(), 1u);
  ASSERT_EQ(b.spheres.size(), 1u);
  EXPECT_FLOAT_EQ(a.spheres[0].radius, 1.0f);
  EXPECT_FLOAT_EQ(b.spheres[0].radius, 1.0f);
  EXPECT_FLOAT_EQ(b.spheres[0].center.z, 2.0f);

  const auto scene_a = Scene::build(a), scene_b = Scene::build(b);
  EXPECT_EQ(scene_a->stats().triangles, scene_b->stats().triangles);
  EXPECT_EQ(scene_a->stats().area_lights, scene_b->stats().area_lights);
  // The lookat rectangle lies in y = 3 facing -y; both see the same gold BSDF.
  SurfaceHit ha, hb;
  const Ray down{Vec3(0.2f, 10, 0.1f), Vec3(0, -1, 0)};
  ASSERT_TRUE(scene_a->intersect(down, ha));
  ASSERT_TRUE(scene_b->intersect(down, hb));
  EXPECT_NEAR(ha.position.y, 3.0f, 1e-4f);
  const Vec3 wo = glm::normalize(Vec3(0.1f, 0.0f, 1.0f)),
             wi = glm::normalize(Vec3(-0.1f, 0.05f, 1.0f));
  const Rgb fa = ha.bsdf->eval({}, wo, wi), fb = hb.bsdf->eval({}, wo, wi);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fa[c], fb[c], 1e-5f);
  EXPECT_GT(fa.x, fa.z);  // gold
}

// Every transform element and attribute Mitsuba 0.6's parser accepts (scene.xsd and its
// scene handler): <lookAt> as well as <lookat>, a lookat without `up` framed by Mitsuba's
// coordinateSystem() of the viewing direction, and the forms it refuses refused here too.
TEST(Loader, MitsubaTransformElementsAsMitsubaReadsThem) {
  const auto dir = test::scratch_dir("transforms");
  std::string camel = small_xml(R"(
  <shape type="rectangle"><transform name="toWorld"><scale x="2" y="1"/>
    <lookAt origin="0, 0.5, 0" target="0, 3, 0"/></transform></shape>)");
  camel.replace(camel.find("<lookat origin=\"0,0,-5\""), 7, "<lookAt");
  const SceneDescription desc = load_scene_description(write_file(dir, "camel.xml", camel));
  EXPECT_TRUE(desc.warnings.empty()) << desc.warnings.front();
  EXPECT_EQ(desc.verdict(), "exact");
  const SceneDescription lower =
      load_scene_description(write_file(dir, "lower.xml", small_xml("")));
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row)
      EXPECT_FLOAT_EQ(desc.camera.to_world[col][row], lower.camera.to_world[col][row]);
  EXPECT_FLOAT_EQ(desc.camera.to_world[3][2], -5.0f);  // the camera did move
  // Facing straight up, Mitsuba's frame has up = (1, 0, 0) and left = (0, 0, 1): the
  // rectangle's long local x runs along world z, its short y along world x.
  ASSERT_EQ(desc.meshes.size(), 2u);
  Vec3 lo(1e9f), hi(-1e9f);
  for (const Vec3& p : desc.meshes[1].positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  EXPECT_NEAR(lo.z, -2.0f, 1e-5f);
  EXPECT_NEAR(hi.z, 2.0f, 1e-5f);
  EXPECT_NEAR(lo.x, -1.0f, 1e-5f);
  EXPECT_NEAR(hi.x, 1.0f, 1e-5f);
  EXPECT_NEAR(lo.y, 0.5f, 1e-6f);
  EXPECT_NEAR(hi.y, 0.5f, 1e-6f);

  struct Case {
    std::string element, problem;
  };
  const std::vector<Case> refused = {
      {R"(<scale value="2" x="1"/>)",
       "line 11: <scale> takes either 'value' or 'x'/'y'/'z', not both"},
      {R"(<scale/>)", "line 11: <scale> needs 'value' or 'x'/'y'/'z'"},
      {R"(<rotate y="1"/>)", "line 11: <rotate> needs an 'angle' (degrees)"},
      {R"(<rotate angle="30"/>)", "line 11: <rotate> needs a non-zero axis"},
      {R"(<lookAt origin="1, 2, 3"/>)", "line 11: <lookAt> needs 'target'"},
      {R"(<lookAt origin="1, 2, 3" target="1, 2, 3"/>)",
       "line 11: <lookAt>: 'origin' and 'target' coincide"},
      {R"(<lookat origin="0, 0, 0" target="0, 2, 0" up="0, 1, 0"/>)",
       "line 11: <lookat>: 'up' is parallel to the viewing direction"},
  };
  for (const Case& c : refused) {
    const std::string path =
        write_file(dir, "bad.xml",
                   small_xml("  <shape type=\"cube\"><transform name=\"toWorld\">\n    " +
                             c.element + "</transform></shape>"));
    const std::string message = load_and_build_error(path);
    EXPECT_NE(message.find("bad.xml: " + c.problem), std::string::npos)
        << c.element << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(Loader, ShapesWithoutABsdfGetMitsubasDefault) {
  const auto dir = test::scratch_dir("default-bsdf");
  // A lamp that names no BSDF: Mitsuba makes it black. A panel that names none: a
  // one-sided diffuse of 0.5, black from behind.
  const auto scene = Scene::build(load_scene_description(write_file(dir, "scene.xml", small_xml(R"(
  <shape type="rectangle"><transform name="toWorld"><translate z="-3"/></transform>
    <emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>
  <shape type="rectangle"><transform name="toWorld"><translate z="3"/></transform></shape>)"))));
  const Vec3 up(0.0f, 0.0f, 1.0f), tilted = glm::normalize(Vec3(0.3f, 0.1f, 1.0f));
  SurfaceHit lamp, front;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.1f, 0.2f, -4), Vec3(0, 0, 1)}, lamp));
  ASSERT_NE(lamp.light, nullptr);
  EXPECT_TRUE(is_black(lamp.bsdf->eval({}, up, tilted)));
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.1f, 0.2f, 5), Vec3(0, 0, -1)}, front));
  EXPECT_EQ(front.light, nullptr);
  EXPECT_NEAR(front.bsdf->eval({}, up, tilted).x, 0.5f * kInvPi, 1e-6f);
  EXPECT_TRUE(is_black(front.bsdf->eval({}, -up, -tilted)));  // one-sided
  for (const std::string& w : scene->warnings())
    EXPECT_EQ(w.find("no material"), std::string::npos) << w;
}
