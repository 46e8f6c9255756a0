// Point, spot and directional lights (delta lights) through every integrator, against exact
// answers: a point light at the centre of a closed diffuse sphere, where the radiance of
// paths of k segments is I a^(k-1) / (pi R^2) everywhere, and a directional light over a
// diffuse floor, where it is a E cos / pi. A scene with more bounces (a floor, a wall and a
// block under a directional light and a spot) checks the MCMC integrators against BDPT.
// Two injected mistakes (DeltaLightFaults) must be noticed: a point light's sample
// MIS-weighted as if BSDF sampling could find it, and a point given an area density.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/registry.h"
#include "emlt/path/connection.h"
#include "emlt/path/path_density.h"
#include "emlt/path/random_walk.h"
#include "emlt/scene/collimated_light.h"
#include "emlt/scene/directional_light.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/point_light.h"
#include "emlt/scene/scene.h"
#include "support/mlt_test_helpers.h"
#include "support/test_scenes.h"

using namespace emlt;

namespace {

constexpr float kAlbedo = 0.5f;

// The inside of a closed sphere of radius 1 round the origin, tessellated finely (the flat
// facets put the walls up to 0.05 % nearer the centre, well below the tolerances), with a
// point light of intensity pi at the centre: paths of k >= 2 segments carry a^(k-1).
SceneDescription point_in_sphere_description(bool spot) {
  SceneDescription d;
  d.source = "point-in-sphere";
  d.materials.push_back({"wall", make_lambertian(Rgb(kAlbedo))});
  MeshDesc m;
  m.name = "sphere";
  m.material = 0;
  const int rings = 64, segments = 128;
  for (int i = 0; i <= rings; ++i) {
    const float theta = kPi * float(i) / float(rings);
    for (int j = 0; j < segments; ++j) {
      const float phi = kTwoPi * float(j) / float(segments);
      m.positions.push_back(
          Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
    }
  }
  const auto index = [&](int i, int j) { return uint32_t(i * segments + (j % segments)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      if (i > 0) m.indices.insert(m.indices.end(), {index(i, j), index(i + 1, j), index(i, j + 1)});
      if (i + 1 < rings)
        m.indices.insert(m.indices.end(), {index(i, j + 1), index(i + 1, j), index(i + 1, j + 1)});
    }
  d.meshes.push_back(m);
  PointLightDesc light;
  light.position = Vec3(0.0f);
  light.intensity = Rgb(kPi);
  if (spot) {
    // A spot pointing down with a wide beam: what it sends upwards is zero, so only the
    // lower half is lit directly; the test below only asks BDPT and PT to agree.
    light.spot = true;
    light.cutoff = 60.0f * kPi / 180.0f;
    light.beam_width = 40.0f * kPi / 180.0f;
    light.orientation = Mat3(Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, -1, 0));
  }
  d.point_lights.push_back(light);
  d.camera = test::camera_at(Vec3(0.1f, 0.2f, -0.3f), Vec3(0.3f, -0.2f, 1.0f), 16);
  d.camera.fov_degrees = 60.0f;
  return d;
}

std::unique_ptr<Scene> point_in_sphere(DeltaLightFaults faults = {}) {
  SceneBuildOptions options;
  options.delta_light_faults = faults;
  return Scene::build(point_in_sphere_description(false), options);
}

// The same sphere lit by a collimated beam of power 4 pi^2 from the centre, hitting the wall
// behind the camera. The spot it lights is a Lambertian point source on the sphere, which
// lights the whole sphere evenly (E = a P / (4 pi R^2): the chord's 1/d^2 and the two
// cosines cancel), so paths of k >= 3 segments carry a^(k-1) / 4 everywhere, and the spot
// itself is out of view.
std::unique_ptr<Scene> beam_in_sphere() {
  SceneDescription d = point_in_sphere_description(false);
  d.point_lights.clear();
  d.collimated_lights.push_back({Vec3(0.0f), Vec3(0.0f, 0.0f, -1.0f), Rgb(4.0f * kPi * kPi)});
  return Scene::build(std::move(d));
}

double beam_sphere_radiance(int max_depth) {
  double sum = 0.0;
  for (int k = 3; k <= max_depth; ++k) sum += 0.25 * std::pow(double(kAlbedo), double(k - 3));
  return sum;
}

double point_sphere_radiance(int max_depth) {
  double sum = 0.0;
  for (int k = 2; k <= max_depth; ++k) sum += std::pow(double(kAlbedo), double(k - 1));
  return sum;
}

// A floor of albedo a under a directional light of irradiance E travelling along
// `travel`, seen from above: every pixel is a E |cos| / pi (the floor cannot see itself;
// it reaches past the view on every side).
SceneDescription sunlit_floor_description(const Vec3& travel, float irradiance) {
  SceneDescription d;
  d.source = "sunlit-floor";
  const int floor = test::add_material(d, make_lambertian(Rgb(kAlbedo)));
  test::add_quad(d, Vec3(-4, 0, -4), Vec3(-4, 0, 4), Vec3(4, 0, 4), Vec3(4, 0, -4), floor);
  d.directional_lights.push_back({travel, Rgb(irradiance)});
  d.camera = test::camera_at(Vec3(0.0f, 3.0f, -1.0f), Vec3(0.0f, 0.0f, 0.5f), 16);
  return d;
}

// A floor, a wall and a block lit by a directional light and a spot: light of every length
// up to the depth, with shadows; the reference is BDPT's.
SceneDescription courtyard_description() {
  SceneDescription d;
  d.source = "courtyard";
  const int grey = test::add_material(d, make_lambertian(Rgb(0.6f)));
  const int red = test::add_material(d, make_lambertian(Rgb(0.7f, 0.2f, 0.2f)));
  test::add_quad(d, Vec3(-3, 0, -3), Vec3(-3, 0, 3), Vec3(3, 0, 3), Vec3(3, 0, -3), grey);
  test::add_quad(d, Vec3(-3, 0, 2), Vec3(-3, 3, 2), Vec3(3, 3, 2), Vec3(3, 0, 2), red);
  // A block: its top and the two faces the camera sees.
  test::add_quad(d, Vec3(-0.5f, 1, -0.5f), Vec3(-0.5f, 1, 0.5f), Vec3(0.5f, 1, 0.5f),
                 Vec3(0.5f, 1, -0.5f), grey);
  test::add_quad(d, Vec3(-0.5f, 0, -0.5f), Vec3(-0.5f, 1, -0.5f), Vec3(0.5f, 1, -0.5f),
                 Vec3(0.5f, 0, -0.5f), grey);
  test::add_quad(d, Vec3(-0.5f, 0, 0.5f), Vec3(-0.5f, 1, 0.5f), Vec3(-0.5f, 1, -0.5f),
                 Vec3(-0.5f, 0, -0.5f), grey);
  d.directional_lights.push_back({glm::normalize(Vec3(1.0f, -2.0f, 1.5f)), Rgb(2.0f)});
  PointLightDesc spot;
  spot.position = Vec3(1.5f, 2.5f, 0.0f);
  spot.intensity = Rgb(4.0f, 3.0f, 2.0f);
  spot.spot = true;
  spot.cutoff = 40.0f * kPi / 180.0f;
  spot.beam_width = 25.0f * kPi / 180.0f;
  const Vec3 axis = glm::normalize(Vec3(-1.0f, -2.0f, 0.5f));
  const Frame frame(axis);
  spot.orientation = Mat3(frame.s, frame.t, frame.n);
  d.point_lights.push_back(spot);
  d.camera = test::camera_at(Vec3(-1.0f, 2.5f, -4.0f), Vec3(0.2f, 0.5f, 0.5f), 16);
  return d;
}

RenderSettings settings_for(int spp, int max_depth, uint64_t seed) {
  RenderSettings s = test::base_settings();
  s.spp = spp;
  s.max_depth = max_depth;
  s.seed = seed;
  return s;
}

double mean_of(const Image& image) {
  double sum = 0.0;
  for (const Rgb& p : image.pixels) sum += (double(p.x) + double(p.y) + double(p.z)) / 3.0;
  return sum / double(image.pixels.size());
}

Image render_with(const std::string& integrator, const Scene& scene, RenderSettings s) {
  return test::render(*make_integrator(integrator), scene, s);
}

// The MCMC integrators' settings: every path in the chains, direct light included.
RenderSettings chain_settings(double mpp, int max_depth, uint64_t seed) {
  RenderSettings s = settings_for(1, max_depth, seed);
  s.mutations_per_pixel = mpp;
  s.bootstrap_samples = 50000;
  s.direct_separate = false;
  return s;
}

// ERPT's settings: `spp` seeds per pixel, a chain of 32 steps per seed on average, every path
// (direct light included) redistributed by the chains.
RenderSettings erpt_settings(int spp, int max_depth, uint64_t seed) {
  RenderSettings s = settings_for(spp, max_depth, seed);
  s.bootstrap_samples = 20000;
  s.direct_separate = false;
  s.erpt_chains = double(spp);
  s.erpt_chain_length = 32;
  return s;
}

}  // namespace

// --- The lights themselves -----------------------------------------------------------

TEST(PointLight, SpotFalloffIsLinearInAngleBetweenBeamAndCutoff) {
  const float cutoff = 30.0f * kPi / 180.0f, beam = 10.0f * kPi / 180.0f;
  PointLight spot(Vec3(0.0f), Frame(Vec3(0, 0, 1)), Rgb(2.0f), SpotProfile{cutoff, beam, nullptr});
  for (float degrees : {0.0f, 5.0f, 10.0f, 15.0f, 20.0f, 25.0f, 29.0f, 31.0f, 90.0f, 150.0f}) {
    const float angle = degrees * kPi / 180.0f;
    const Vec3 w(std::sin(angle), 0.0f, std::cos(angle));
    const float expected = angle <= beam     ? 2.0f
                           : angle >= cutoff ? 0.0f
                                             : 2.0f * (cutoff - angle) / (cutoff - beam);
    EXPECT_NEAR(spot.emitted(Vec3(0.0f), w).x, expected, 1e-4f) << degrees << " degrees";
  }
}

TEST(PointLight, LightSamplesAreTheIrradianceAtNormalIncidence) {
  PointLight point(Vec3(1, 2, 3), Frame(Vec3(0, 0, 1)), Rgb(5.0f), std::nullopt);
  const auto sample = point.sample_direct(Vec3(1, 0, 3), Vec2(0.3f, 0.7f));
  ASSERT_TRUE(sample.has_value());
  EXPECT_TRUE(sample->delta);
  EXPECT_EQ(sample->pdf, 1.0f);
  EXPECT_NEAR(sample->radiance.x, 5.0f / 4.0f, 1e-6f);
  EXPECT_NEAR(sample->wi.y, 1.0f, 1e-6f);
  EXPECT_EQ(point.pdf_direct(Vec3(0.0f), Vec3(1, 2, 3), Vec3(0.0f), Vec3(0, 1, 0)), 0.0f);
  // Emission: from the point, uniform over the sphere, the intensity along the ray.
  const auto emission = point.sample_emission(Vec2(0.5f), Vec2(0.2f, 0.9f));
  ASSERT_TRUE(emission.has_value());
  EXPECT_EQ(emission->ray.origin, Vec3(1, 2, 3));
  EXPECT_EQ(emission->pdf_position, 1.0f);
  EXPECT_NEAR(emission->pdf_direction, 1.0f / (4.0f * kPi), 1e-7f);
  EXPECT_EQ(emission->radiance, Rgb(5.0f));
}

TEST(DirectionalLight, LightSamplesAndEmissionRaysCarryTheIrradiance) {
  DirectionalLight sun(Vec3(0.0f, -1.0f, 0.0f), Rgb(3.0f));
  sun.set_scene_bounds(Vec3(0.0f), 2.0f);
  const auto sample = sun.sample_direct(Vec3(0.5f, 0.0f, 0.5f), Vec2(0.1f));
  ASSERT_TRUE(sample.has_value());
  EXPECT_TRUE(sample->delta);
  EXPECT_EQ(sample->wi, Vec3(0.0f, 1.0f, 0.0f));
  EXPECT_EQ(sample->radiance, Rgb(3.0f));
  EXPECT_EQ(sun.emitted(Vec3(0.0f), Vec3(0.0f, 1.0f, 0.0f)), Rgb(3.0f));
  EXPECT_EQ(sun.emitted(Vec3(0.0f), glm::normalize(Vec3(0.1f, 1.0f, 0.0f))), Rgb(0.0f));
  for (float u : {0.0f, 0.3f, 0.99f}) {
    const auto e = sun.sample_emission(Vec2(u, 1.0f - u), Vec2(0.5f));
    ASSERT_TRUE(e.has_value());
    EXPECT_EQ(e->ray.direction, Vec3(0.0f, -1.0f, 0.0f));
    EXPECT_NEAR(e->ray.origin.y, 2.0f, 1e-5f);  // on the disk beyond the scene's sphere
    EXPECT_LE(std::hypot(e->ray.origin.x, e->ray.origin.z), 2.0f + 1e-5f);
    EXPECT_NEAR(e->pdf_position, 1.0f / (kPi * 4.0f), 1e-7f);
  }
}

// --- The path layer ------------------------------------------------------------------

TEST(DeltaLightPaths, NoCameraWalkEndsOnADeltaLightAndNoneIsSeenFromTheLens) {
  const auto scene = point_in_sphere();
  Rng rng(3, 0);
  PathVertices light;
  ASSERT_GE(generate_light_subpath(*scene, rng, {3, -1}, light), 2);
  EXPECT_EQ(light[0].kind, VertexKind::PointEmitter);
  EXPECT_TRUE(light[0].is_delta_emitter());
  // The point light's own vertex, straight to the lens: nothing.
  const auto lens = sample_camera_vertex(*scene, light[0], Vec2(0.5f));
  // (The light, at the sphere's centre, is in the camera's view.)
  ASSERT_TRUE(lens.has_value());
  EXPECT_EQ(connect_vertices(*scene, nullptr, light[0], *lens, nullptr), Rgb(0.0f));
  // x0 x1 x2(lens): s = 0 is impossible, s = 1 and 2 are.
  VertexDensity path[3] = {density_of(light[0]), density_of(light[1]), {}};
  path[2].camera = true;
  EXPECT_FALSE(split_is_possible(path, 0));
  EXPECT_TRUE(split_is_possible(path, 1));
  EXPECT_TRUE(split_is_possible(path, 2));
  VertexDensity direct_view[2] = {density_of(light[0]), {}};
  direct_view[1].camera = true;
  EXPECT_FALSE(split_is_possible(direct_view, 1));
}

// Each BDPT strategy alone, without MIS weights, estimates the light of its own path
// length exactly; a camera walk never finds the point (s = 0 gives nothing).
TEST(DeltaLightPaths, EveryUnweightedBdptStrategyIsUnbiasedForItsPathLength) {
  const auto scene = point_in_sphere();
  for (int k = 2; k <= 4; ++k) {
    for (int s = 0; s <= k; ++s) {
      const int t = k + 1 - s;
      BdptOptions options;
      options.mis = false;
      options.only_s = s;
      options.only_t = t;
      RenderSettings settings = settings_for(t == 1 ? 1024 : 64, k, uint64_t(10 * k + s));
      const double value =
          mean_of(test::render(BidirectionalPathTracer(options), *scene, settings));
      const double expected = std::pow(double(kAlbedo), double(k - 1));
      if (s == 0) {
        EXPECT_EQ(value, 0.0) << "t=" << t;
      } else {
        EXPECT_NEAR(value, expected, (t == 1 ? 0.03 : 0.02) * expected) << "s=" << s << " t=" << t;
      }
    }
  }
}

// --- Every integrator against the exact answers -------------------------------------

TEST(DeltaLightIntegrators, PointLightInASphereGivesTheExactRadiance) {
  const auto scene = point_in_sphere();
  const int depth = 5;
  const double exact = point_sphere_radiance(depth);
  for (const char* name : {"pt", "bdpt", "ptracer"}) {
    // Light tracing alone splats few particles per pixel: it needs more of them.
    const int spp = std::string(name) == "ptracer" ? 1024 : 64;
    const double value = mean_of(render_with(name, *scene, settings_for(spp, depth, 5)));
    EXPECT_NEAR(value, exact, 0.015 * exact) << name;
  }
  const double direct = mean_of(render_with("direct", *scene, settings_for(16, -1, 5)));
  EXPECT_NEAR(direct, double(kAlbedo), 0.01 * kAlbedo) << "direct";
  for (const char* name : {"mlt", "gamlt", "memlt", "emlt", "pssmlt", "mmlt"}) {
    const double value = mean_of(render_with(name, *scene, chain_settings(400, depth, 5)));
    EXPECT_NEAR(value, exact, 0.03 * exact) << name;
  }
  const double erpt = mean_of(render_with("erpt", *scene, erpt_settings(16, depth, 5)));
  EXPECT_NEAR(erpt, exact, 0.03 * exact) << "erpt";
}

// Only light tracing finds a beam: the path tracer's image is black (as Mitsuba's), every
// integrator with light subpaths gives the exact radiance.
TEST(DeltaLightIntegrators, CollimatedBeamInASphereGivesTheExactRadianceByLightTracing) {
  const auto scene = beam_in_sphere();
  const int depth = 5;
  const double exact = beam_sphere_radiance(depth);
  EXPECT_EQ(mean_of(render_with("pt", *scene, settings_for(16, depth, 5))), 0.0);
  for (const char* name : {"bdpt", "ptracer"}) {
    const double value = mean_of(render_with(name, *scene, settings_for(1024, depth, 5)));
    EXPECT_NEAR(value, exact, 0.02 * exact) << name;
  }
  for (const char* name : {"mlt", "gamlt", "memlt", "emlt", "mmlt"}) {
    const double value = mean_of(render_with(name, *scene, chain_settings(400, depth, 5)));
    EXPECT_NEAR(value, exact, 0.03 * exact) << name;
  }
  // ERPT's seeds are BDPT's: their light tracing finds the beam.
  const double erpt = mean_of(render_with("erpt", *scene, erpt_settings(256, depth, 5)));
  EXPECT_NEAR(erpt, exact, 0.03 * exact) << "erpt";
}

TEST(DeltaLightIntegrators, DirectionalLightOnAFloorGivesTheExactRadiance) {
  const Vec3 travel = glm::normalize(Vec3(1.0f, -2.0f, 0.5f));
  const auto scene = Scene::build(sunlit_floor_description(travel, 2.0f));
  const double exact = double(kAlbedo) * 2.0 * std::abs(double(travel.y)) / M_PI;
  for (const char* name : {"direct", "pt", "bdpt", "ptracer"}) {
    const Image image =
        render_with(name, *scene, settings_for(std::string(name) == "ptracer" ? 1024 : 64, 5, 9));
    EXPECT_NEAR(mean_of(image), exact, 0.01 * exact) << name;
    // The light sample alone is exact at every pixel (BSDF samples find nothing more);
    // light tracing's splats are noisy per pixel.
    if (std::string(name) != "direct" && std::string(name) != "pt") continue;
    for (const Rgb& p : image.pixels) ASSERT_NEAR(p.x, exact, 1e-3 * exact) << name;
  }
  for (const char* name : {"mlt", "gamlt", "memlt", "emlt", "pssmlt", "mmlt"}) {
    const double value = mean_of(render_with(name, *scene, chain_settings(200, 5, 9)));
    EXPECT_NEAR(value, exact, 0.02 * exact) << name;
  }
  const double erpt = mean_of(render_with("erpt", *scene, erpt_settings(16, 5, 9)));
  EXPECT_NEAR(erpt, exact, 0.02 * exact) << "erpt";
}

// Shadows, colour and several bounces under a directional light and a spot: every
// integrator converges to BDPT's image, tile by tile.
TEST(DeltaLightIntegrators, CourtyardConvergesToBdptInEveryIntegrator) {
  const auto scene = Scene::build(courtyard_description());
  RenderSettings reference_settings = settings_for(4096, 5, 1);
  const Image reference = render_with("bdpt", *scene, reference_settings);
  ASSERT_GT(mean_of(reference), 0.05);
  test::expect_converged_to(render_with("pt", *scene, settings_for(2048, 5, 2)), reference, 4, 0.03,
                            0.02);
  for (const char* name : {"mlt", "gamlt", "memlt", "emlt", "pssmlt", "mmlt"}) {
    SCOPED_TRACE(name);
    test::expect_converged_to(render_with(name, *scene, chain_settings(2000, 5, 3)), reference, 2,
                              0.06, 0.04);
  }
  SCOPED_TRACE("erpt");
  test::expect_converged_to(render_with("erpt", *scene, erpt_settings(128, 5, 3)), reference, 2,
                            0.06, 0.04);
}

TEST(DeltaLightIntegrators, SpotInASphereAgreesBetweenThePathTracerAndBdpt) {
  const auto scene = Scene::build(point_in_sphere_description(true));
  const Image reference = render_with("bdpt", *scene, settings_for(1024, 4, 1));
  test::expect_converged_to(render_with("pt", *scene, settings_for(1024, 4, 2)), reference, 4, 0.04,
                            0.015);
}

// --- Injected mistakes --------------------------------------------------------------

TEST(DeltaLightInjectedBugs, MisWeightingTheLightSampleIsCaught) {
  DeltaLightFaults faults;
  faults.mis_weighted_light_sample = true;
  const auto scene = point_in_sphere(faults);
  const double exact = point_sphere_radiance(2);
  const double value = mean_of(render_with("direct", *scene, settings_for(16, -1, 5)));
  std::printf("[ info     ] direct with the light sample MIS-weighted: %.4f of the exact value\n",
              value / exact);
  EXPECT_LT(value, 0.97 * exact) << "a light sample weighted against BSDF sampling loses light";
}

TEST(DeltaLightInjectedBugs, AnAreaDensityForThePointIsCaught) {
  DeltaLightFaults faults;
  faults.area_density = true;
  const auto scene = point_in_sphere(faults);
  const double exact = point_sphere_radiance(5);
  const double bdpt = mean_of(render_with("bdpt", *scene, settings_for(64, 5, 5)));
  EXPECT_GT(std::abs(bdpt - exact), 0.05 * exact) << "bdpt " << bdpt << " exact " << exact;
  const double mlt = mean_of(render_with("mlt", *scene, chain_settings(400, 5, 5)));
  std::printf("[ info     ] with an area density: bdpt %.4f, mlt %.4f of the exact value\n",
              bdpt / exact, mlt / exact);
  EXPECT_GT(std::abs(mlt - exact), 0.05 * exact) << "mlt " << mlt << " exact " << exact;
}
