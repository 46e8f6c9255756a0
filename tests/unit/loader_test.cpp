// Scene loaders: JSON and Mitsuba XML agree on the shipped Cornell box, bad input gives a
// one-line error naming the file, unsupported Mitsuba features are reported.
#include "emlt/scene/loaders/loader.h"

#include <gtest/gtest.h>

#include <functional>

#include "emlt/core/error.h"
#include "emlt/integrators/registry.h"
#include "emlt/run/integrator.h"
#include "emlt/run/scene_settings.h"
#include "emlt/scene/loaders/obj_loader.h"
#include "emlt/scene/scene.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::write_file;

using test::error_of;

std::string load_and_build_error(const std::string& path, const SceneDefines& defines = {}) {
  return error_of([&] { Scene::build(load_scene_description(path, defines)); });
}

bool any_contains(const std::vector<std::string>& lines, const std::string& needle) {
  for (const std::string& line : lines)
    if (line.find(needle) != std::string::npos) return true;
  return false;
}

Rgb total_power(const Scene& scene) {
  Rgb power(0.0f);
  for (size_t i = 0; i < scene.lights().size(); ++i) power += scene.lights().light(i).power();
  return power;
}

constexpr const char* kLightOnlyObj = "v 0 1 0\nv 1 1 0\nv 0 1 1\nf 1 3 2\n";

// A JSON scene with one emissive rectangle and whatever `extra_shapes` adds.
std::string small_json(const std::string& camera_extra, const std::string& extra_shapes) {
  return R"({"camera": {"lookat": {"origin": [0,0,-5], "target": [0,0,0], "up": [0,1,0]}, "fov": 40)" +
         camera_extra + R"(},
  "shapes": [{"type": "rectangle", "emission": [1,1,1], "material": {"type": "diffuse"}})" +
         extra_shapes + "]}";
}

std::string small_xml(const std::string& body) {
  return R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film>
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter>
    <bsdf type="diffuse"/></shape>
)" + body +
         "\n</scene>\n";
}

}  // namespace

TEST(CornellBox, JsonAndXmlDescribeTheSameScene) {
  const SceneDescription json_desc =
      load_scene_description(test::source_path("scenes/cornell-box/scene.json"));
  const SceneDescription xml_desc =
      load_scene_description(test::source_path("scenes/cornell-box/scene.xml"));
  EXPECT_TRUE(json_desc.warnings.empty()) << json_desc.warnings.front();
  EXPECT_TRUE(xml_desc.warnings.empty()) << xml_desc.warnings.front();
  EXPECT_EQ(json_desc.camera.width, 256);
  EXPECT_EQ(xml_desc.camera.width, 256);
  EXPECT_EQ(json_desc.render.said("--spp"), xml_desc.render.said("--spp"));
  EXPECT_EQ(json_desc.render.integrator, xml_desc.render.integrator);
  EXPECT_EQ(json_desc.render.said("--max-depth"), xml_desc.render.said("--max-depth"));

  const auto json_scene = Scene::build(json_desc);
  const auto xml_scene = Scene::build(xml_desc);
  EXPECT_EQ(json_scene->stats().triangles, 32u);
  EXPECT_EQ(xml_scene->stats().triangles, 32u);
  EXPECT_EQ(json_scene->stats().area_lights, 2u);
  EXPECT_EQ(xml_scene->stats().area_lights, 2u);
  EXPECT_EQ(json_scene->stats().dropped_degenerate_triangles, 0u);
  // Lambertian emitter: power = pi * area * radiance, light 130 mm x 105 mm.
  const Rgb expected_power = kPi * 130.0f * 105.0f * Rgb(17, 12, 4);
  for (const Scene* scene : {json_scene.get(), xml_scene.get()})
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(total_power(*scene)[c], expected_power[c], 1e-4f * expected_power[c]);

  for (const Vec2 raster :
       {Vec2(0.5f, 0.5f), Vec2(128, 128), Vec2(200.3f, 17.7f), Vec2(255.5f, 255.5f)}) {
    const Ray a = json_scene->camera().generate_ray(raster, Vec2(0.5f));
    const Ray b = xml_scene->camera().generate_ray(raster, Vec2(0.5f));
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(a.origin[c], b.origin[c], 1e-3f);
      EXPECT_NEAR(a.direction[c], b.direction[c], 1e-6f);
    }
  }

  int hits = 0;
  const Vec3 wi_local = glm::normalize(Vec3(0.3f, -0.2f, 0.9f));
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      const Vec2 raster(16.0f * x + 8.0f, 16.0f * y + 8.0f);
      const Ray ray = json_scene->camera().generate_ray(raster, Vec2(0.5f));
      SurfaceHit a, b;
      const bool hit_a = json_scene->intersect(ray, a), hit_b = xml_scene->intersect(ray, b);
      ASSERT_EQ(hit_a, hit_b) << x << "," << y;
      if (!hit_a) continue;
      ++hits;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.position[c], b.position[c], 1e-2f);
      const Vec3 wo_a = a.shading.to_local(-ray.direction),
                 wo_b = b.shading.to_local(-ray.direction);
      const Rgb fa = a.bsdf->eval({}, wo_a, wi_local), fb = b.bsdf->eval({}, wo_b, wi_local);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(fa[c], fb[c], 1e-6f);
      EXPECT_GT(max_component(fa), 0.0f);
      EXPECT_EQ(a.light == nullptr, b.light == nullptr);
      const Rgb ea = a.emitted(-ray.direction), eb = b.emitted(-ray.direction);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(ea[c], eb[c], 1e-6f);
    }
  }
  EXPECT_EQ(hits, 256);  // the box fills the view
}

TEST(CornellBox, RedWallIsOnTheLeftAndLightIsVisible) {
  const auto scene =
      Scene::build(load_scene_description(test::source_path("scenes/cornell-box/scene.json")));
  const Vec3 wo(0, 0, 1), wi = glm::normalize(Vec3(0.2f, 0.1f, 1.0f));
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(scene->camera().generate_ray(Vec2(8, 128), Vec2(0.5f)), hit));
  EXPECT_GT(hit.position.x, 540.0f);
  Rgb f = hit.bsdf->eval({}, wo, wi);
  EXPECT_GT(f.x, 5.0f * f.y);  // red
  ASSERT_TRUE(scene->intersect(scene->camera().generate_ray(Vec2(248, 128), Vec2(0.5f)), hit));
  EXPECT_LT(hit.position.x, 15.0f);
  f = hit.bsdf->eval({}, wo, wi);
  EXPECT_GT(f.y, 2.0f * f.x);  // green
  // The light spans raster rows ~32-40 at the centre column (ceiling y = 548.8, camera at
  // y = 273, light z in [227, 332], tan(fov/2) = 12.5/35).
  ASSERT_TRUE(scene->intersect(scene->camera().generate_ray(Vec2(128, 36), Vec2(0.5f)), hit));
  EXPECT_NE(hit.light, nullptr);
  EXPECT_NEAR(hit.emitted(Vec3(0, -1, 0)).x, 17.0f, 1e-4f);
}

TEST(Loader, DefinesOverrideDefaultsInXmlAndJson) {
  const SceneDefines defines = {{"width", "64"}, {"height", "48"}, {"spp", "4"}};
  for (const char* file : {"scenes/cornell-box/scene.xml", "scenes/cornell-box/scene.json"}) {
    const SceneDescription desc = load_scene_description(test::source_path(file), defines);
    EXPECT_EQ(desc.camera.width, 64) << file;
    EXPECT_EQ(desc.camera.height, 48) << file;
    EXPECT_EQ(desc.render.said("--spp"), "4") << file;
  }
  const auto dir = test::scratch_dir("defines");
  const std::string json =
      write_file(dir, "undefined.json", small_json(R"(, "width": "$size")", ""));
  const std::string message = error_of([&] { load_scene_description(json); });
  EXPECT_NE(message.find("undefined.json"), std::string::npos) << message;
  EXPECT_NE(message.find("$size"), std::string::npos) << message;
  EXPECT_EQ(load_scene_description(json, {{"size", "20"}}).camera.width, 20);

  const std::string xml = write_file(dir, "param.xml", small_xml(R"(
  <shape type="sphere"><float name="radius" value="$r"/><point name="center" x="$x" y="0" z="0"/></shape>
  <default name="r" value="0.25"/>)"));
  SceneDescription desc = load_scene_description(xml, {{"x", "3"}});
  ASSERT_EQ(desc.spheres.size(), 1u);
  EXPECT_FLOAT_EQ(desc.spheres[0].radius, 0.25f);
  EXPECT_FLOAT_EQ(desc.spheres[0].center.x, 3.0f);
  const std::string missing = error_of([&] { load_scene_description(xml); });
  EXPECT_NE(missing.find("param.xml: line 11"), std::string::npos) << missing;
  EXPECT_NE(missing.find("$x"), std::string::npos) << missing;
}

// Mitsuba's hideEmitters (and JSON's hide_emitters) reach the render settings, with no
// warning: every integrator honours it (the conformance scenes light-hide-emitters*).
TEST(Loader, HideEmittersIsASetting) {
  const auto dir = test::scratch_dir("hide-emitters");
  const SceneDescription xml = load_scene_description(write_file(dir, "hide.xml", small_xml(R"(
  <integrator type="path"><boolean name="hideEmitters" value="true"/></integrator>)")));
  EXPECT_EQ(xml.render.said("--hide-emitters"), "true");
  EXPECT_TRUE(xml.warnings.empty());
  EXPECT_FALSE(load_scene_description(write_file(dir, "show.xml", small_xml("")))
                   .render.said("--hide-emitters") == "true");
  std::string json = small_json("", "");
  json.insert(1, R"("integrator": {"type": "pt", "hide_emitters": true}, )");
  EXPECT_TRUE(load_scene_description(write_file(dir, "hide.json", json))
                  .render.said("--hide-emitters") == "true");
}

TEST(Loader, BadInputGivesOneLineErrorNamingFileAndProblem) {
  const auto dir = test::scratch_dir("bad");
  write_file(dir, "light.obj", kLightOnlyObj);
  std::string absurd_xml = small_xml("");
  for (size_t at; (at = absurd_xml.find("value=\"16\"")) != std::string::npos;)
    absurd_xml.replace(at, 10, "value=\"100000\"");
  struct Case {
    std::string file, content, expected_file, expected_problem;
  };
  const std::vector<Case> cases = {
      {"malformed.json", R"({"camera": {"fov": 40,)", "malformed.json", "malformed JSON"},
      {"malformed.xml", "<scene version=\"0.6.0\">\n<shape type=\"obj\">\n</scene>\n",
       "malformed.xml", "malformed XML at line 3"},
      {"missing_obj.json", small_json("", R"(, {"type": "obj", "file": "nowhere.obj"})"),
       "nowhere.obj", "not found"},
      {"missing_obj.xml",
       small_xml(R"(<shape type="obj"><string name="filename" value="nowhere.obj"/></shape>)"),
       "nowhere.obj", "not found"},
      {"missing_env.json",
       small_json("", "").replace(1, 0,
                                  R"("environment": {"type": "envmap", "file": "sky.exr"}, )"),
       "missing_env.json", "environment map"},
      {"missing_env.xml",
       small_xml(R"(<emitter type="envmap"><string name="filename" value="sky.exr"/></emitter>)"),
       "sky.exr", "not found"},
      {"nan_transform.json",
       small_json("", R"(, {"type": "cube", "transform": [{"scale": 1e39}]})"),
       "nan_transform.json", "NaN"},
      {"nan_transform.xml",
       small_xml(
           R"(<shape type="cube"><transform name="toWorld"><translate x="nan"/></transform></shape>)"),
       "nan_transform.xml", "not a finite number"},
      {"nan_camera.json",
       R"({"camera": {"lookat": {"origin": [0,0,0], "target": [0,1,0], "up": [0,1,0]}},
         "shapes": [{"type": "rectangle", "emission": 1}]})",
       "nan_camera.json", "NaN"},
      {"no_emitter.json", R"({"shapes": [{"type": "cube"}]})", "no_emitter.json",
       "scene has no emitter"},
      {"no_emitter.xml", "<scene version=\"0.6.0\"><shape type=\"cube\"/></scene>",
       "no_emitter.xml", "scene has no emitter"},
      {"zero_resolution.json", small_json(R"(, "width": 0)", ""), "zero_resolution.json",
       "camera.width: must be a whole number of pixels from 1 to 16384 (got 0)"},
      {"absurd_resolution.json", small_json(R"(, "width": 100000, "height": 100000)", ""),
       "absurd_resolution.json", "camera.width: must be a whole number of pixels from 1 to 16384"},
      {"absurd_resolution.xml", absurd_xml, "absurd_resolution.xml",
       "line 6: 'width' must be a whole number of pixels from 1 to 16384 (got 100000)"},
      {"unknown_material.json", small_json("", R"(, {"type": "cube", "material": "nope"})"),
       "unknown_material.json", "unknown material 'nope'"},
      {"unknown_material.xml", small_xml(R"(<shape type="cube"><ref id="nope"/></shape>)"),
       "unknown_material.xml", "unknown reference id 'nope'"},
      {"bad_index.json", small_json("", R"(, {"type": "obj", "file": "bad_index.obj"})"),
       "bad_index.obj", "out of range"},
      {"wrong_type.json", small_json("", R"(, {"type": "sphere", "radius": "big"})"),
       "wrong_type.json", "shapes[1].radius: expected a number"},
      {"missing_key.json", small_json("", R"(, {"type": "obj"})"), "missing_key.json",
       "missing required key 'file'"},
      {"no_faces.json", small_json("", R"(, {"type": "obj", "file": "empty.obj"})"), "empty.obj",
       "no faces"},
  };
  write_file(dir, "bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  write_file(dir, "empty.obj", "v 0 0 0\nv 1 0 0\n");
  for (const Case& c : cases) {
    const std::string path = write_file(dir, c.file, c.content);
    const std::string message = load_and_build_error(path);
    EXPECT_NE(message.find(c.expected_file), std::string::npos) << c.file << ": " << message;
    EXPECT_NE(message.find(c.expected_problem), std::string::npos) << c.file << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << c.file << ": " << message;
  }
  EXPECT_NE(load_and_build_error((dir / "scene.obj").string()).find("unknown scene format"),
            std::string::npos);
  EXPECT_NE(
      load_and_build_error((dir / "absent.json").string()).find("absent.json: file not found"),
      std::string::npos);
}

TEST(Loader, UnsupportedMitsubaElementsAreReportedWithNameAndLine) {
  const auto dir = test::scratch_dir("mitsuba-warnings");
  const std::string xml = write_file(dir, "scene.xml", small_xml(R"(
  <shape type="heightfield"><string name="filename" value="x.exr"/></shape>
  <medium type="homogeneous" id="fog"/>
  <emitter type="laser"><rgb name="power" value="1"/></emitter>
  <shape type="cube"><bsdf type="hk"/><float name="wobble" value="2"/></shape>
  <shape type="sphere"><bsdf type="roughconductor"><string name="distribution" value="trowbridge"/></bsdf></shape>
  <shape type="disk"><bsdf type="roughplastic"><float name="alphaU" value="0.1"/><float name="alphaV" value="0.3"/></bsdf></shape>)"));
  const SceneDescription desc = load_scene_description(xml);
  for (const char* needle : {"'heightfield'", "<medium", "'laser'", "'hk'", "'wobble'",
                             "distribution 'trowbridge'", "anisotropic roughness"})
    EXPECT_TRUE(any_contains(desc.warnings, needle)) << needle;
  EXPECT_TRUE(any_contains(desc.warnings, "scene.xml: line 11:"))
      << desc.warnings.front();       // the heightfield shape
  EXPECT_EQ(desc.meshes.size(), 3u);  // emissive rectangle, cube, disk (the heightfield is skipped)
  EXPECT_EQ(desc.spheres.size(), 1u);

  const std::string json = write_file(dir, "scene.json", small_json(R"(, "colour": 3)", ""));
  EXPECT_TRUE(
      any_contains(load_scene_description(json).warnings, "unknown key 'colour' in camera"));
}

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

// Mitsuba's particle tracer is emlt's, with its depth parameters; granularity (the light
// paths of a work unit) only schedules the work.
TEST(Loader, XmlParticleTracer) {
  const auto dir = test::scratch_dir("ptracer");
  const std::string xml = write_file(dir, "scene.xml", R"(<scene version="0.6.0">
  <integrator type="ptracer"><integer name="maxDepth" value="6"/>
    <integer name="rrDepth" value="3"/><integer name="granularity" value="1000"/></integrator>
  <sensor type="perspective"><float name="fov" value="30"/>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
  <emitter type="constant"><spectrum name="radiance" value="0.5"/></emitter>
  <shape type="sphere"/>
</scene>)");
  const SceneDescription desc = load_scene_description(xml);
  EXPECT_EQ(desc.render.integrator, "ptracer");
  EXPECT_EQ(desc.render.said("--max-depth"), "6");
  EXPECT_EQ(desc.render.said("--rr-depth"), "3");
  EXPECT_NE(make_integrator(desc.render.integrator), nullptr);
}

// Mitsuba's ptracer reads no hideEmitters and draws the lights seen directly, so the flag is
// noted and dropped; bruteForce, an image emlt does not render, is a divergence (said before
// the render, refused by --strict), but only when switched on.
TEST(Loader, XmlParticleTracerHideEmittersAndBruteForce) {
  const auto dir = test::scratch_dir("ptracer-flags");
  const auto scene = [&](const std::string& name, const std::string& flags) {
    return load_scene_description(write_file(dir, name, R"(<scene version="0.6.0">
  <integrator type="ptracer">)" + flags + R"(</integrator>
  <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/>
    <integer name="height" value="8"/></film></sensor>
  <shape type="sphere"><emitter type="area"><spectrum name="radiance" value="1"/></emitter></shape>
</scene>)"));
  };
  const SceneDescription hidden = scene("hide.xml", R"(<boolean name="hideEmitters" value="true"/>
    <boolean name="bruteForce" value="false"/>)");
  EXPECT_FALSE(hidden.render.said("--hide-emitters"));
  EXPECT_TRUE(
      any_contains(hidden.warnings, "'hideEmitters' is not a parameter of Mitsuba's ptracer"));
  EXPECT_TRUE(hidden.divergences.empty()) << hidden.divergences.front().message;
  const SceneDescription brute = scene("brute.xml", R"(<boolean name="bruteForce" value="true"/>)");
  ASSERT_EQ(brute.divergences.size(), 1u);
  EXPECT_NE(brute.divergences.front().message.find("'bruteForce' is not supported"),
            std::string::npos);
  // The path tracer still reads the flag.
  EXPECT_TRUE(load_scene_description(write_file(dir, "path.xml", R"(<scene version="0.6.0">
  <integrator type="path"><boolean name="hideEmitters" value="true"/></integrator>
  <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/>
    <integer name="height" value="8"/></film></sensor>
  <shape type="sphere"/>
</scene>)"))
                  .render.said("--hide-emitters") == "true");
}

// highQualityEdges samples just outside the image in Mitsuba, which changes the border
// pixels under a filter wider than a pixel: approximated there (emlt's border pixels are
// Mitsuba's without it), a note with a box filter, nothing when false.
TEST(Loader, HighQualityEdgesIsApproximatedUnderAWideFilter) {
  const auto dir = test::scratch_dir("high-quality-edges");
  const auto film = [&](const std::string& name, const std::string& edges,
                        const std::string& filter) {
    return load_scene_description(write_file(dir, name, R"(<scene version="0.6.0">
  <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/>
    <integer name="height" value="8"/><boolean name="highQualityEdges" value=")" + edges +
                                                           R"("/>)" + filter + R"(</film></sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>)"));
  };
  EXPECT_EQ(film("gaussian.xml", "true", "").verdict(), "approximated: 1 item");
  const SceneDescription box = film("box.xml", "true", R"(<rfilter type="box"/>)");
  EXPECT_EQ(box.verdict(), "exact");
  EXPECT_TRUE(any_contains(box.warnings, "'highQualityEdges' changes nothing with a box filter"));
  const SceneDescription off = film("off.xml", "false", "");
  EXPECT_EQ(off.verdict(), "exact");
  EXPECT_TRUE(off.warnings.empty()) << off.warnings.front();
}

TEST(Loader, XmlSensorFilmSamplerAndIntegrator) {
  const auto dir = test::scratch_dir("sensor");
  const std::string xml = write_file(dir, "scene.xml", R"(<scene version="0.6.0">
  <integrator type="bdpt"><integer name="maxDepth" value="7"/></integrator>
  <sensor type="thinlens">
    <float name="fov" value="30"/><string name="fovAxis" value="smaller"/>
    <float name="apertureRadius" value="0.1"/><float name="focusDistance" value="4"/>
    <transform name="toWorld"><lookat origin="1, 2, 3" target="1, 2, 4" up="0, 1, 0"/></transform>
    <sampler type="ldsampler"><integer name="sampleCount" value="64"/></sampler>
    <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="20"/>
      <rfilter type="gaussian"/></film>
  </sensor>
  <emitter type="constant"><spectrum name="radiance" value="0.5"/></emitter>
  <shape type="sphere"><bsdf type="dielectric"><string name="intIOR" value="water"/></bsdf></shape>
</scene>)");
  const SceneDescription desc = load_scene_description(xml);
  EXPECT_EQ(desc.render.integrator, "bdpt");
  EXPECT_EQ(desc.render.said("--max-depth"), "7");
  EXPECT_EQ(desc.render.said("--spp"), "64");
  EXPECT_EQ(desc.camera.width, 40);
  EXPECT_EQ(desc.camera.height, 20);
  EXPECT_FLOAT_EQ(desc.camera.fov_degrees, 30.0f);
  EXPECT_EQ(desc.camera.fov_axis, CameraDesc::FovAxis::Smaller);
  EXPECT_FLOAT_EQ(desc.camera.aperture_radius, 0.1f);
  EXPECT_FLOAT_EQ(desc.camera.focus_distance, 4.0f);
  EXPECT_FLOAT_EQ(desc.camera.to_world[3][2], 3.0f);
  EXPECT_EQ(desc.environment.kind, EnvironmentDesc::Kind::Constant);
  EXPECT_FLOAT_EQ(desc.environment.radiance.y, 0.5f);
  EXPECT_EQ(desc.camera.filter.kind, PixelFilterDesc::Kind::Gaussian);
  EXPECT_FLOAT_EQ(desc.camera.filter.stddev, 0.5f);
  EXPECT_FALSE(any_contains(desc.warnings, "gaussian"));
  const auto scene = Scene::build(desc);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0, 0, -3), Vec3(0, 0, 1)}, hit));
  EXPECT_TRUE(hit.bsdf->has_delta_lobe());  // smooth dielectric
}

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
  const std::string path = write_file(dir, "mesh.obj",
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

TEST(ShippedScenes, LoadAndBuildWithoutWarnings) {
  for (const char* file : {"scenes/cornell-glass/scene.json", "scenes/env-sky/scene.json",
                           "scenes/env-sky/scene.xml", "scenes/staircase/scene.json",
                           "scenes/bedroom/scene.json", "scenes/kitchen/scene.json",
                           "scenes/classroom/scene.json", "scenes/breakfast-room/scene.json",
                           "scenes/sponza-like/scene.json", "scenes/door-ajar/scene.json",
                           "scenes/caustic-pool/scene.json"}) {
    const SceneDescription desc = load_scene_description(test::source_path(file));
    EXPECT_TRUE(desc.warnings.empty()) << file << ": " << desc.warnings.front();
    const auto scene = Scene::build(desc);
    EXPECT_GT(scene->stats().triangles + scene->stats().spheres, 0u) << file;
    EXPECT_TRUE(scene->warnings().empty()) << file;
  }
  const auto sky =
      Scene::build(load_scene_description(test::source_path("scenes/env-sky/scene.json")));
  ASSERT_NE(sky->environment(), nullptr);
  EXPECT_EQ(sky->stats().area_lights, 0u);
  // tools/scenes/make_sky.py and the renderer agree on the lat-long mapping: the sun sits in
  // the script's SUN_DIRECTION, ~1e4 times brighter than the sky.
  const Vec3 sun = glm::normalize(Vec3(-0.45f, 0.6f, -0.65f));
  const float sun_radiance = luminance(sky->environment()->radiance(sun));
  EXPECT_GT(sun_radiance, 500.0f);
  EXPECT_LT(luminance(sky->environment()->radiance(Vec3(0, 1, 0))), 1e-3f * sun_radiance);
  EXPECT_LT(luminance(sky->environment()->radiance(-sun)), 1e-3f * sun_radiance);
}

TEST(Loader, FilmFilterFollowsMitsubaDefaultsAndJsonOptIn) {
  const auto dir = test::scratch_dir("film-filter");
  // Mitsuba's film filters with a Gaussian unless told otherwise; a box when told so.
  std::string xml = small_xml("");
  const std::string box = write_file(dir, "box.xml", xml);
  xml.replace(xml.find("<rfilter type=\"box\"/>"), std::string("<rfilter type=\"box\"/>").size(), "");
  const std::string by_default = write_file(dir, "default.xml", xml);
  EXPECT_EQ(load_scene_description(box).camera.filter.kind, PixelFilterDesc::Kind::Box);
  const SceneDescription gaussian = load_scene_description(by_default);
  EXPECT_EQ(gaussian.camera.filter.kind, PixelFilterDesc::Kind::Gaussian);
  EXPECT_EQ(gaussian.verdict(), "exact");
  // JSON scenes keep the box unless they ask.
  EXPECT_EQ(load_scene_description(write_file(dir, "plain.json", small_json("", ""))).camera.filter.kind,
            PixelFilterDesc::Kind::Box);
  const SceneDescription json = load_scene_description(
      write_file(dir, "tent.json", small_json(R"(, "filter": {"type": "tent", "radius": 1.5})", "")));
  EXPECT_EQ(json.camera.filter.kind, PixelFilterDesc::Kind::Tent);
  EXPECT_FLOAT_EQ(json.camera.filter.radius, 1.5f);
  const std::string bad =
      write_file(dir, "bad.json", small_json(R"(, "filter": {"type": "sinc"})", ""));
  EXPECT_NE(load_and_build_error(bad).find("bad.json: camera.filter.type: unknown filter 'sinc'"),
            std::string::npos)
      << load_and_build_error(bad);
}

TEST(Loader, MitsubaSettingsThatChangeNoImageKeepTheVerdictExact) {
  const auto dir = test::scratch_dir("exact-settings");
  // Public scenes carry clip planes, a pinhole's focus distance, tone mapping and MLT
  // tuning: none changes the converged image, so the scene stays exact.
  std::string xml = small_xml("");
  xml.replace(xml.find("<float name=\"fov\" value=\"40\"/>"), 0,
              "<float name=\"nearClip\" value=\"0.1\"/><float name=\"farClip\" value=\"100\"/>"
              "<float name=\"focusDistance\" value=\"3\"/>");
  xml.replace(xml.find("<sensor"), 0,
              "<integrator type=\"mlt\"><integer name=\"directSamples\" value=\"4\"/>"
              "<boolean name=\"twoStage\" value=\"true\"/><boolean name=\"strictNormals\" "
              "value=\"false\"/></integrator>\n");
  const SceneDescription exact = load_scene_description(write_file(dir, "exact.xml", xml));
  EXPECT_EQ(exact.verdict(), "exact");
  EXPECT_EQ(exact.render.integrator, "mlt");
  EXPECT_TRUE(any_contains(exact.warnings, "nearClip 0.1 and farClip 100 are not applied"));
  // Mitsuba's MLT does not read strictNormals and treats shading normals strictly, as emlt
  // does then; the parameter is a note.
  EXPECT_TRUE(exact.strict_normals);
  EXPECT_TRUE(any_contains(exact.warnings, "'strictNormals' is not a parameter of Mitsuba's mlt"));
}

// The path and direct integrators read strictNormals (default false), and emlt renders
// either: the scene stays exact and the description says which.
TEST(Loader, MitsubaStrictNormalsIsReadByThePathAndDirectIntegrators) {
  const auto dir = test::scratch_dir("strict-normals");
  const auto with = [&](const std::string& name, const std::string& integrator) {
    std::string xml = small_xml("");
    xml.replace(xml.find("<sensor"), 0, integrator + "\n");
    return load_scene_description(write_file(dir, name, xml));
  };
  const SceneDescription none = with("none.xml", "");
  EXPECT_FALSE(none.strict_normals);  // Mitsuba's default integrator is its path tracer
  const SceneDescription path = with("path.xml", "<integrator type=\"path\"/>");
  EXPECT_FALSE(path.strict_normals);
  const SceneDescription strict = with(
      "strict.xml",
      "<integrator type=\"direct\"><boolean name=\"strictNormals\" value=\"true\"/></integrator>");
  EXPECT_TRUE(strict.strict_normals);
  EXPECT_EQ(strict.verdict(), "exact");
  EXPECT_TRUE(with("bdpt.xml", "<integrator type=\"bdpt\"/>").strict_normals);
  EXPECT_TRUE(with("ptracer.xml", "<integrator type=\"ptracer\"/>").strict_normals);
}

// What steers only how Mitsuba samples (a sampler's seed and sequence, a rough BSDF's
// visible-normal sampling, a light's sampling weight, an integrator's sample counts and
// work units) is a note: the scene stays exact and --strict takes it. What changes the
// image is still an item.
TEST(Loader, SamplingOnlyParametersAreNotesNotItems) {
  const auto dir = test::scratch_dir("sampling-only");
  std::string xml = small_xml(R"(
  <shape type="sphere"><bsdf type="roughconductor"><boolean name="sampleVisible" value="false"/></bsdf></shape>
  <shape type="disk"><bsdf type="roughdielectric"><boolean name="sampleVisible" value="true"/></bsdf></shape>
  <shape type="cube"><bsdf type="roughplastic"><boolean name="sampleVisible" value="false"/></bsdf></shape>
  <shape type="rectangle"><transform name="toWorld"><translate z="2"/></transform>
    <emitter type="area"><rgb name="radiance" value="1"/><float name="samplingWeight" value="3"/></emitter></shape>
  <emitter type="constant"><float name="samplingWeight" value="0.5"/></emitter>)");
  xml.replace(xml.find("<film"), 0,
              "<sampler type=\"ldsampler\"><integer name=\"sampleCount\" value=\"4\"/>"
              "<integer name=\"seed\" value=\"7\"/><integer name=\"dimension\" value=\"8\"/>"
              "<integer name=\"scramble\" value=\"3\"/></sampler>");
  const std::string direct =
      R"(<integrator type="direct"><integer name="shadingSamples" value="4"/></integrator>)";
  const std::string mlt =
      R"(<integrator type="mlt"><integer name="workUnits" value="8"/><integer name="timeout" value="60"/>
    <float name="probFactor" value="20"/><integer name="firstStageSizeReduction" value="4"/></integrator>)";
  for (const std::string& integrator : {direct, mlt}) {
    std::string scene = xml;
    scene.replace(scene.find("<sensor"), 0, integrator + "\n  ");
    const SceneDescription desc = load_scene_description(write_file(dir, "exact.xml", scene));
    EXPECT_EQ(desc.verdict(), "exact") << desc.divergences.front().message;
    for (const char* needle :
         {"'sampleVisible' of <bsdf type=\"roughconductor\"> steers only how Mitsuba samples",
          "'sampleVisible' of <bsdf type=\"roughdielectric\">",
          "'sampleVisible' of <bsdf type=\"roughplastic\">",
          "'seed', 'scramble', 'dimension' of <sampler type=\"ldsampler\"> steer only the sample "
          "sequence",
          "'samplingWeight' of <emitter type=\"area\">",
          "'samplingWeight' of <emitter type=\"constant\">"})
      EXPECT_TRUE(any_contains(desc.warnings, needle)) << needle;
    EXPECT_TRUE(any_contains(
        desc.warnings, integrator == direct
                           ? "'shadingSamples'"
                           : "'probFactor', 'firstStageSizeReduction', 'workUnits', 'timeout'"));
  }
  // A malformed value is refused as Mitsuba refuses it.
  std::string malformed = xml;
  malformed.replace(malformed.find("value=\"false\""), 13, "value=\"maybe\"");
  EXPECT_NE(load_and_build_error(write_file(dir, "malformed.xml", malformed))
                .find("'sampleVisible' must be true or false, not 'maybe'"),
            std::string::npos);
  // Beside them, a parameter that changes the image is still counted.
  std::string counted = xml;
  counted.replace(counted.find("<integer name=\"seed\""), 0,
                  "<integer name=\"wobble\" value=\"1\"/>");
  EXPECT_EQ(load_scene_description(write_file(dir, "counted.xml", counted)).verdict(),
            "unsupported: 1 item");
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
  for (const std::string& w : scene->warnings()) EXPECT_EQ(w.find("no material"), std::string::npos) << w;
}

TEST(Loader, SceneWhoseShapesWereAllSkippedNamesThem) {
  const auto dir = test::scratch_dir("all-skipped");
  const std::string path = write_file(dir, "skipped.xml", R"(<scene version="0.6.0">
  <emitter type="constant"/>
  <shape type="heightfield"/>
  <shape type="hair"><string name="filename" value="x.hair"/></shape>
</scene>)");
  EXPECT_NE(load_and_build_error(path).find(
                "skipped.xml: scene has no geometry: every shape was skipped (<shape "
                "type=\"heightfield\"> at line 3, <shape type=\"hair\"> at line 4)"),
            std::string::npos)
      << load_and_build_error(path);
}

TEST(Loader, AMediumIsUnsupportedOnlyWhereSomethingUsesIt) {
  const auto dir = test::scratch_dir("medium");
  const std::string unused = R"(<medium type="homogeneous" id="fog"/>)";
  EXPECT_EQ(load_scene_description(write_file(dir, "unused.xml", small_xml(unused))).verdict(), "exact");
  const std::string used = unused + R"(
  <shape type="sphere"><ref name="interior" id="fog"/><bsdf type="dielectric"/></shape>)";
  EXPECT_NE(load_scene_description(write_file(dir, "used.xml", small_xml(used))).verdict(), "exact");
}

TEST(Loader, ParametersMitsubaItselfIgnoresKeepTheVerdictExact) {
  const auto dir = test::scratch_dir("mitsuba-ignores");
  // Exporters write roughness onto smooth materials and a file name into the film; Mitsuba's
  // plugins read neither, so ignoring them renders what Mitsuba renders.
  std::string xml = small_xml(R"(
  <shape type="sphere"><bsdf type="dielectric"><float name="alpha" value="0.001"/></bsdf></shape>
  <shape type="disk"><bsdf type="conductor"><float name="alpha" value="0.1"/></bsdf></shape>)");
  xml.replace(xml.find("<rfilter"), 0, "<string name=\"filename\" value=\"out.png\"/>");
  const SceneDescription desc = load_scene_description(write_file(dir, "scene.xml", xml));
  EXPECT_EQ(desc.verdict(), "exact");
  EXPECT_TRUE(any_contains(desc.warnings, "parameter 'alpha' of a smooth dielectric ignored"));
  // On a rough material an unknown parameter is still an unsupported item.
  xml.replace(xml.find("type=\"conductor\""), std::string("type=\"conductor\"").size(),
              "type=\"roughconductor\"><float name=\"wobble\" value=\"1\"/");
  EXPECT_EQ(load_scene_description(write_file(dir, "rough.xml", xml)).verdict(),
            "unsupported: 1 item");
}

// A scene description holds what the file says about rendering and nothing more: a file
// that names no integrator and no sample count leaves them to the engine and the command line.
TEST(Loader, TheDescriptionCarriesOnlyWhatTheFileSaysAboutRendering) {
  const auto dir = test::scratch_dir("render-request");
  const SceneDescription silent =
      load_scene_description(write_file(dir, "silent.xml", small_xml("")));
  EXPECT_TRUE(silent.render.integrator.empty());
  EXPECT_TRUE(silent.render.options.empty());
  const RenderSettings engine;
  const RenderSettings s = settings_for(silent.render);
  EXPECT_EQ(s.integrator, engine.integrator);
  EXPECT_EQ(s.spp, engine.spp);
  EXPECT_EQ(s.max_depth, engine.max_depth);
  const SceneDescription said = load_scene_description(write_file(dir, "said.xml", small_xml(R"(
  <integrator type="bdpt"><integer name="maxDepth" value="4"/></integrator>)")));
  EXPECT_EQ(said.render.integrator, "bdpt");
  EXPECT_EQ(said.render.said("--max-depth"), "4");
  EXPECT_FALSE(said.render.said("--rr-depth"));  // not said: the engine's
  EXPECT_EQ(settings_for(said.render).rr_depth, engine.rr_depth);
  EXPECT_EQ(settings_for(said.render).max_depth, 4);
}
