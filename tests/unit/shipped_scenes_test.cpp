// The shipped scenes: JSON and Mitsuba XML agree on the Cornell box, and every shipped scene
// loads and builds without a warning.
#include <gtest/gtest.h>

#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

Rgb total_power(const Scene& scene) {
  Rgb power(0.0f);
  for (size_t i = 0; i < scene.lights().size(); ++i) power += scene.lights().light(i).power();
  return power;
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

TEST(ShippedScenes, LoadAndBuildWithoutWarnings) {
  for (const char* file :
       {"scenes/cornell-glass/scene.json", "scenes/env-sky/scene.json", "scenes/env-sky/scene.xml",
        "scenes/staircase/scene.json", "scenes/bedroom/scene.json", "scenes/kitchen/scene.json",
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
