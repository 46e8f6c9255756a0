// Textured scenes rendered end to end: a checkerboard plane under a constant sky (every
// cell has the analytic radiance albedo x sky), and the shipped textured room (Mitsuba
// XML with bitmap textures, bump-mapped Beckmann metal, nonlinear rough plastic and
// glass), which must load without warnings and render the same image with `pt` as with
// the independent `bdpt` estimator, region by region.
#include <gtest/gtest.h>

#include "emlt/integrators/registry.h"
#include "emlt/run/integrator.h"
#include "emlt/run/scene_settings.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

RenderResult render(const std::string& integrator, const Scene& scene, int spp, uint64_t seed) {
  RenderSettings s;
  s.integrator = integrator;
  s.spp = spp;
  s.seed = seed;
  s.progress = false;
  s.max_depth = settings_for(scene.description().render).max_depth;
  ProgressReporter progress(false);
  return make_integrator(integrator)->render(scene, s, progress);
}

// Mean over the pixels [x0, x1) x [y0, y1).
Rgb region_mean(const Image& image, int x0, int y0, int x1, int y1) {
  DVec3 sum(0.0);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) sum += DVec3(image.at(x, y));
  return Rgb(sum / double((x1 - x0) * (y1 - y0)));
}

TEST(TexturedScene, CheckerboardPlaneUnderConstantSkyHasAlbedoTimesSkyPerCell) {
  // Camera straight above a one-sided diffuse plane: the plane sees only the sky, so the
  // radiance leaving a cell is exactly its albedo times the sky radiance.
  const Rgb sky(1.0f, 0.9f, 0.8f);
  const Rgb color0(0.8f, 0.5f, 0.2f), color1(0.1f, 0.3f, 0.6f);
  SceneDescription d;
  d.source = "checker-plane";
  d.materials.push_back({"checks", make_lambertian(make_checkerboard_texture(color0, color1))});
  MeshDesc plane;
  plane.name = "plane";
  plane.positions = {{-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}};
  plane.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // cells: x < 0 / x > 0 times y < 0 / y > 0
  plane.indices = {0, 1, 2, 0, 2, 3};
  plane.material = 0;
  d.meshes.push_back(plane);
  d.environment.kind = EnvironmentDesc::Kind::Constant;
  d.environment.radiance = sky;
  d.camera.to_world = look_at_matrix(Vec3(0, 0, 3), Vec3(0, 0, 0), Vec3(0, 1, 0));
  d.camera.fov_degrees = 40.0f;
  d.camera.width = d.camera.height = 16;
  const auto scene = Scene::build(std::move(d));
  const Image image = render("pt", *scene, 256, 3).image;

  // Which cell a pixel block sees, from the camera's own centre ray (so the test does not
  // restate the camera convention); blocks stay 2 px clear of the cell boundaries.
  int checked = 0;
  for (const auto& [x0, y0] : {std::pair{1, 1}, std::pair{10, 1}, std::pair{1, 10}, std::pair{10, 10}}) {
    const Ray ray = scene->camera().generate_ray(Vec2(x0 + 2.5f, y0 + 2.5f), Vec2(0.5f));
    SurfaceHit hit;
    ASSERT_TRUE(scene->intersect(ray, hit));
    const bool even = (hit.position.x < 0.0f) == (hit.position.y < 0.0f);
    const Rgb expected = (even ? color0 : color1) * sky;
    const Rgb mean = region_mean(image, x0, y0, x0 + 5, y0 + 5);
    // Light sampling of the sky under MIS leaves a little noise (~0.4% here).
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(mean[c], expected[c], 0.015f * expected[c]) << x0 << "," << y0;
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

TEST(TexturedRoom, LoadsWithoutWarningsAndPtAgreesWithBdptPerRegion) {
  const SceneDefines defines = {{"size", "24"}};
  SceneDescription desc =
      load_scene_description(test::source_path("scenes/textured-room/scene.xml"), defines);
  EXPECT_TRUE(desc.warnings.empty()) << desc.warnings.front();
  const auto scene = Scene::build(std::move(desc));
  ASSERT_TRUE(scene->warnings().empty()) << scene->warnings().front();

  const Image pt = render("pt", *scene, 1024, 11).image;
  const Image bdpt = render("bdpt", *scene, 256, 13).image;
  ASSERT_EQ(pt.width, 24);
  const double pt_mean = luminance(region_mean(pt, 0, 0, 24, 24));
  const double bdpt_mean = luminance(region_mean(bdpt, 0, 0, 24, 24));
  EXPECT_GT(pt_mean, 0.05);
  EXPECT_NEAR(pt_mean, bdpt_mean, 0.02 * bdpt_mean);
  // 3 x 3 regions of 8 x 8 pixels: walls, floor, teapot, glass, light.
  for (int ry = 0; ry < 3; ++ry)
    for (int rx = 0; rx < 3; ++rx) {
      const Rgb a = region_mean(pt, 8 * rx, 8 * ry, 8 * rx + 8, 8 * ry + 8);
      const Rgb b = region_mean(bdpt, 8 * rx, 8 * ry, 8 * rx + 8, 8 * ry + 8);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a[c], b[c], 0.05 * b[c] + 0.005) << "region " << rx << "," << ry << " c" << c;
    }
}

}  // namespace
