// Mitsuba 0.6's orthographic camera through the integrators that build paths: its film
// point x0 is the projection of x1 (camera.h), x1's camera-side density is |cos1| / A and
// the edge x0 x1 carries |cos1| alone. Checked on the path layer (the connection's value
// and film point, the densities the walks store against those recomputed from the path),
// inside an emissive sphere whose radiance is known for every path length (each unweighted BDPT
// strategy), and on a small room against the path tracer, which only traces camera rays
// (and matches Mitsuba: conformance scene camera-orthographic), in every integrator. Two
// injected mistakes (CameraFaults) must be noticed, and a checkpoint's film point must lie on
// the film.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/registry.h"
#include "emlt/path/connection.h"
#include "emlt/path/path.h"
#include "emlt/path/path_state.h"
#include "emlt/path/random_walk.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "support/mlt_test_helpers.h"
#include "support/test_scenes.h"

using namespace emlt;

namespace {

// An orthographic camera at `eye` looking at `target`, its film 2 half_width wide (square).
CameraDesc orthographic_camera(Vec3 eye, Vec3 target, float half_width, int size) {
  CameraDesc c = test::camera_at(eye, target, size);
  c.projection = CameraDesc::Projection::Orthographic;
  c.to_world[0] *= half_width;
  c.to_world[1] *= half_width;
  return c;
}

constexpr float kAlbedo = 0.5f, kEmission = 1.0f;

// The inside of a diffuse sphere of radius 1 that emits kEmission everywhere (an analytic
// sphere, normals inwards): the radiance along every path of k segments is le a^(k-1), and
// G between two of its points is 1/4 whatever they are (the cosines are d/2 each), so every
// strategy's estimate is bounded. An orthographic film inside it, tilted.
SceneDescription sphere_seen_orthographically_description() {
  SceneDescription d;
  d.source = "orthographic-sphere";
  const int wall = test::add_material(d, make_lambertian(Rgb(kAlbedo)));
  SphereDesc sphere;
  sphere.material = wall;
  sphere.emission = Rgb(kEmission);
  sphere.flip_normals = true;
  d.spheres.push_back(sphere);
  d.camera = orthographic_camera(Vec3(0.1f, 0.2f, -0.5f), Vec3(0.5f, -0.4f, 1.0f), 0.4f, 16);
  return d;
}

std::unique_ptr<Scene> sphere_seen_orthographically(SceneBuildOptions options = {}) {
  return Scene::build(sphere_seen_orthographically_description(), options);
}

double sphere_radiance(int max_depth) {
  double sum = 0.0;
  for (int k = 1; k <= max_depth; ++k) sum += kEmission * std::pow(double(kAlbedo), double(k - 1));
  return sum;
}

// A floor, a back wall, a block and a light above, seen from above at an angle: shadows,
// interreflection and cosines that vary across the film.
std::unique_ptr<Scene> room_seen_orthographically(SceneBuildOptions options = {}) {
  SceneDescription d;
  d.source = "orthographic-room";
  const int grey = test::add_material(d, make_lambertian(Rgb(0.6f)));
  const int red = test::add_material(d, make_lambertian(Rgb(0.7f, 0.25f, 0.2f)));
  const int light = test::add_material(d, make_lambertian(Rgb(0.0f)));
  test::add_quad(d, Vec3(-2, 0, -2), Vec3(-2, 0, 2), Vec3(2, 0, 2), Vec3(2, 0, -2), grey);
  test::add_quad(d, Vec3(-2, 0, 1.5f), Vec3(-2, 2, 1.5f), Vec3(2, 2, 1.5f), Vec3(2, 0, 1.5f), red);
  // A block: its top and the two faces the camera sees.
  test::add_quad(d, Vec3(-0.4f, 0.6f, -0.4f), Vec3(-0.4f, 0.6f, 0.4f), Vec3(0.4f, 0.6f, 0.4f),
                 Vec3(0.4f, 0.6f, -0.4f), grey);
  test::add_quad(d, Vec3(-0.4f, 0, -0.4f), Vec3(-0.4f, 0.6f, -0.4f), Vec3(0.4f, 0.6f, -0.4f),
                 Vec3(0.4f, 0, -0.4f), grey);
  test::add_quad(d, Vec3(-0.4f, 0, 0.4f), Vec3(-0.4f, 0.6f, 0.4f), Vec3(-0.4f, 0.6f, -0.4f),
                 Vec3(-0.4f, 0, -0.4f), grey);
  // The light faces down.
  test::add_quad(d, Vec3(0.6f, 1.8f, -0.3f), Vec3(1.2f, 1.8f, -0.3f), Vec3(1.2f, 1.8f, 0.3f),
                 Vec3(0.6f, 1.8f, 0.3f), light, Rgb(12.0f, 10.0f, 8.0f));
  d.camera = orthographic_camera(Vec3(-1.0f, 3.0f, -3.0f), Vec3(0.1f, 0.4f, 0.3f), 1.6f, 16);
  return Scene::build(std::move(d), options);
}

RenderSettings settings_for(int spp, int max_depth, uint64_t seed) {
  RenderSettings s = test::base_settings();
  s.spp = spp;
  s.max_depth = max_depth;
  s.seed = seed;
  return s;
}

// The MCMC integrators' settings: every path in the chains, direct light included.
RenderSettings chain_settings(double mpp, int max_depth, uint64_t seed) {
  RenderSettings s = settings_for(1, max_depth, seed);
  s.mutations_per_pixel = mpp;
  s.bootstrap_samples = 20000;
  s.direct_separate = false;
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

}  // namespace

// --- The path layer ------------------------------------------------------------------

// A light vertex reaches the film at its projection, the pixel the camera ray through that
// film point sees it in, with f_s |cos1| / A; no walk reaches the film (t = 0).
TEST(OrthographicPaths, ALightVertexReachesTheFilmAtItsProjection) {
  const auto scene = room_seen_orthographically();
  const Camera& camera = scene->camera();
  ASSERT_TRUE(camera.is_orthographic());
  const float area = 3.2f * 3.2f;
  // A camera ray through a raster point finds a floor or block point x1 ...
  const Vec2 raster(5.3f, 9.6f);
  const Ray ray = camera.generate_ray(raster, Vec2(0.5f));
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(ray, hit));
  PathVertex x1 = make_surface_vertex(hit);
  // ... which, as a light vertex, connects back to that film point and raster.
  const auto lens = sample_camera_vertex(*scene, x1, Vec2(0.9f, 0.1f));
  ASSERT_TRUE(lens.has_value());
  EXPECT_EQ(lens->kind, VertexKind::OrthographicCamera);
  EXPECT_NEAR(glm::length(lens->position - ray.origin), 0.0f, 1e-5f);
  EXPECT_NEAR(lens->raster.x, raster.x, 1e-3f);
  EXPECT_NEAR(lens->raster.y, raster.y, 1e-3f);
  EXPECT_EQ(lens->pdf_from_eye, 1.0f);  // discrete: x0 follows from x1
  // The light vertex x0 at the light's centre, lighting x1: the connection x1 -> film is
  // f_s |cos1| / A.
  PathVertex x0;
  x0.kind = VertexKind::Surface;
  x0.position = Vec3(0.9f, 1.8f, 0.0f);
  x0.normal = Vec3(0.0f, -1.0f, 0.0f);
  x0.shading = Frame(x0.normal);
  const float cos1 = std::abs(glm::dot(x1.normal, camera.forward()));
  const Rgb f = connect_vertices(*scene, &x0, x1, *lens, nullptr);
  const float expected = 0.6f / kPi * cos1 / area;
  EXPECT_NEAR(f.x, expected, 1e-4f * expected);
  // Points behind the film, or projecting outside it, reach no film point.
  PathVertex behind = x1;
  behind.position = ray.origin - 0.5f * camera.forward();
  EXPECT_FALSE(sample_camera_vertex(*scene, behind, Vec2(0.5f)).has_value());
  PathVertex aside = x1;
  aside.position = ray.origin + 5.0f * glm::normalize(glm::cross(camera.forward(), Vec3(0, 1, 0)));
  EXPECT_FALSE(sample_camera_vertex(*scene, aside, Vec2(0.5f)).has_value());
}

// The densities a camera walk stores are those the path layer recomputes from the path:
// x1 has |cos1| / A from the camera side (no 1/d^2), the film point 1.
TEST(OrthographicPaths, CameraWalkDensitiesAreTheRecomputedOnes) {
  const auto scene = room_seen_orthographically();
  const float area = 3.2f * 3.2f;
  Rng rng(5, 0);
  int checked = 0;
  for (int i = 0; i < 64; ++i) {
    PathVertices camera, light;
    const Vec2 raster(16.0f * rng.uniform(), 16.0f * rng.uniform());
    if (generate_camera_subpath(*scene, rng, raster, rng.uniform2(), {4, -1}, camera) < 3) continue;
    generate_light_subpath(*scene, rng, {2, -1}, light);
    ASSERT_GE(light.size(), 1u);
    EXPECT_EQ(camera[0].kind, VertexKind::OrthographicCamera);
    const float cos1 = std::abs(glm::dot(camera[1].normal, scene->camera().forward()));
    EXPECT_NEAR(camera[1].pdf_from_eye, cos1 / area, 1e-5f * cos1 / area);
    Path path;
    ASSERT_TRUE(join_subpaths(*scene, light, 1, camera, int(camera.size()), path));
    Path recomputed = path;
    recompute_densities(*scene, recomputed);
    for (size_t v = 0; v < path.vertices.size(); ++v) {
      const float a = path.vertices[v].pdf_from_eye, b = recomputed.vertices[v].pdf_from_eye;
      EXPECT_NEAR(a, b, 1e-4f * std::max(a, b)) << "vertex " << v;
    }
    ++checked;
  }
  EXPECT_GT(checked, 16);
}

// A chain's path goes through a checkpoint whole; one whose film point is off the film, or
// whose camera vertex is a perspective lens's, is refused.
TEST(OrthographicPaths, ACheckpointedFilmPointMustLieOnTheFilm) {
  const auto scene = room_seen_orthographically();
  Rng rng(9, 0);
  PathVertices camera, light;
  Path path;
  for (int i = 0; i < 32 && path.vertices.empty(); ++i) {
    if (generate_camera_subpath(*scene, rng, Vec2(8.3f, 7.1f), rng.uniform2(), {3, -1}, camera) < 3)
      continue;
    if (generate_light_subpath(*scene, rng, {1, -1}, light) < 1) continue;
    if (!join_subpaths(*scene, light, 1, camera, 3, path)) path.vertices.clear();
  }
  ASSERT_EQ(path.vertices.size(), 4u);
  const PathCodec codec(*scene);
  const auto round_trip = [&](const Path& p) {
    StateWriter out;
    codec.save(p, out);
    StateReader in(out.data());
    return codec.load(in);
  };
  EXPECT_EQ(round_trip(path).vertices.back().position, path.vertices.back().position);
  Path off_film = path;
  off_film.vertices.back().position += 0.1f * scene->camera().forward();
  EXPECT_THROW(round_trip(off_film), StateError);
  Path beside_film = path;
  beside_film.vertices.back().position +=
      4.0f * glm::normalize(glm::cross(scene->camera().forward(), Vec3(0, 1, 0)));
  EXPECT_THROW(round_trip(beside_film), StateError);
  Path pinhole = path;
  pinhole.vertices.back().kind = VertexKind::Camera;
  EXPECT_THROW(round_trip(pinhole), StateError);
}

// --- Each strategy alone ---------------------------------------------------------------

// Each BDPT strategy alone, without MIS weights, estimates the light of its own path length
// exactly, the light tracing ones (t = 1) included; t = 0 does not exist.
TEST(OrthographicStrategies, EveryUnweightedBdptStrategyIsUnbiasedForItsPathLength) {
  const auto scene = sphere_seen_orthographically();
  for (int k = 1; k <= 3; ++k) {
    for (int s = 0; s <= k; ++s) {
      const int t = k + 1 - s;
      BdptOptions options;
      options.mis = false;
      options.only_s = s;
      options.only_t = t;
      RenderSettings settings = settings_for(t == 1 ? 256 : 32, k, uint64_t(10 * k + s));
      const double value =
          mean_of(test::render(BidirectionalPathTracer(options), *scene, settings));
      const double expected = kEmission * std::pow(double(kAlbedo), double(k - 1));
      EXPECT_NEAR(value, expected, (t == 1 ? 0.03 : 0.02) * expected) << "s=" << s << " t=" << t;
    }
  }
}

// --- Every integrator against the path tracer --------------------------------------

TEST(OrthographicIntegrators, SphereGivesTheExactRadiance) {
  const auto scene = sphere_seen_orthographically();
  const int depth = 4;
  const double exact = sphere_radiance(depth);
  for (const char* name : {"pt", "bdpt", "ptracer"}) {
    const int spp = std::string(name) == "ptracer" ? 256 : 32;
    EXPECT_NEAR(mean_of(render_with(name, *scene, settings_for(spp, depth, 5))), exact,
                0.015 * exact)
        << name;
  }
}

// A crop window renders its part of the film: the importance integrates to one over the
// window, so the evenly bright sphere keeps its exact radiance in every integrator (with
// the whole film's 1/A, light tracing and the chains would give the window's share of it).
TEST(OrthographicIntegrators, ACropWindowGivesTheExactRadiance) {
  SceneDescription d = sphere_seen_orthographically_description();
  d.camera.crop_x = 3;
  d.camera.crop_y = 5;
  d.camera.crop_width = 8;
  d.camera.crop_height = 6;
  const auto scene = Scene::build(std::move(d));
  ASSERT_EQ(scene->camera().width(), 8);
  const int depth = 3;
  const double exact = sphere_radiance(depth);
  for (const char* name : {"pt", "bdpt", "ptracer"}) {
    const int spp = std::string(name) == "ptracer" ? 512 : 64;
    EXPECT_NEAR(mean_of(render_with(name, *scene, settings_for(spp, depth, 7))), exact,
                0.015 * exact)
        << name;
  }
  EXPECT_NEAR(mean_of(render_with("mlt", *scene, chain_settings(256, depth, 7))), exact,
              0.02 * exact);
}

TEST(OrthographicIntegrators, RoomConvergesToThePathTracer) {
  const auto scene = room_seen_orthographically();
  const Image reference = render_with("pt", *scene, settings_for(2048, 5, 1));
  ASSERT_GT(mean_of(reference), 0.05);
  {
    SCOPED_TRACE("bdpt");
    test::expect_converged_to(render_with("bdpt", *scene, settings_for(512, 5, 2)), reference, 4,
                              0.03, 0.015);
  }
  {
    SCOPED_TRACE("ptracer");
    test::expect_converged_to(render_with("ptracer", *scene, settings_for(1024, 5, 3)), reference,
                              4, 0.05, 0.02);
  }
  // The chains: every mutation that moves x_{k-1} moves the film point with it. (EMLT's
  // ensembles are the noisiest at a small budget: 3000 mutations per pixel.)
  for (const char* name : {"mlt", "gamlt", "memlt", "emlt", "pssmlt", "mmlt"}) {
    SCOPED_TRACE(name);
    const double mpp = std::string(name) == "emlt" ? 3000 : 1000;
    test::expect_converged_to(render_with(name, *scene, chain_settings(mpp, 5, 4)), reference, 2,
                              0.05, 0.04);
  }
}

// --- Injected mistakes --------------------------------------------------------------

// The film's area taken in camera space, without to_world's scale (Mitsuba normalises W_e
// by the scaled film's area): light tracing splats 1/A too much.
TEST(OrthographicInjectedBugs, AnUnscaledFilmAreaIsCaught) {
  SceneBuildOptions options;
  options.camera_faults.orthographic_unscaled_area = true;
  const auto scene = sphere_seen_orthographically(options);
  const int depth = 3;
  const double exact = sphere_radiance(depth);
  const double ptracer = mean_of(render_with("ptracer", *scene, settings_for(64, depth, 5)));
  // BDPT weights its light tracing strategies low here: a smaller but clear error.
  const double bdpt = mean_of(render_with("bdpt", *scene, settings_for(64, depth, 5)));
  std::printf(
      "[ info     ] with the film's unscaled area: ptracer %.4f, bdpt %.4f of the exact value\n",
      ptracer / exact, bdpt / exact);
  EXPECT_GT(std::abs(ptracer - exact), 0.1 * exact) << "ptracer " << ptracer << " exact " << exact;
  EXPECT_GT(std::abs(bdpt - exact), 0.015 * exact) << "bdpt " << bdpt << " exact " << exact;
}

// x1 given the 1/d^2 of a perspective camera's spreading rays from the camera side: BDPT is
// blind to it (its MIS weights still sum to one, and a camera walk's first throughput is 1
// whatever the density), but the chains' bidirectional mutation proposes by that density,
// and MLT's image takes the wrong shape (0.025 of the reference tile by tile when right).
TEST(OrthographicInjectedBugs, ASpreadingDensityOfTheFirstVertexIsCaught) {
  const auto scene = room_seen_orthographically();
  const Image reference = render_with("pt", *scene, settings_for(1024, 5, 1));
  SceneBuildOptions options;
  options.camera_faults.orthographic_spreading_density = true;
  const auto faulty = room_seen_orthographically(options);
  const test::TileDeviation mlt =
      test::tile_deviation(render_with("mlt", *faulty, chain_settings(1000, 5, 4)), reference, 2);
  std::printf("[ info     ] mlt with a spreading density: worst tile %.4f off the path tracer's\n",
              mlt.worst);
  EXPECT_GT(mlt.worst, 0.08);
}
