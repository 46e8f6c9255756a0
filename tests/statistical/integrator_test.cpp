// Integrators against analytic answers. Every scene here is built in code, so the
// expected radiance is known exactly; thresholds are several standard errors wide.
#include <gtest/gtest.h>

#include <cstring>

#include "emlt/integrators/direct_integrator.h"
#include "emlt/integrators/path_tracer.h"
#include "emlt/sampling/direct_lighting.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "support/test_scenes.h"

using namespace emlt;

namespace {

using test::add_material;
using test::add_quad;
using test::camera_at;

std::unique_ptr<Scene> emissive_box(float albedo, float le) {
  return test::emissive_box(Rgb(albedo), le);
}

struct ImageStats {
  double mean = 0.0, standard_error = 0.0;
};

ImageStats stats_of(const Image& image, int channel = 1) {
  double sum = 0.0, sum2 = 0.0;
  for (const Rgb& p : image.pixels) {
    sum += p[channel];
    sum2 += double(p[channel]) * p[channel];
  }
  const double n = double(image.pixels.size()), mean = sum / n;
  return {mean, std::sqrt(std::max(sum2 / n - mean * mean, 0.0) / n)};
}

RenderResult render(const Integrator& integrator, const Scene& scene, RenderSettings s) {
  s.progress = false;
  ProgressReporter progress(false);
  return integrator.render(scene, s, progress);
}

}  // namespace

class ClosedBoxTest : public ::testing::TestWithParam<int> {};

TEST_P(ClosedBoxTest, PathTracerMatchesGeometricSeries) {
  const float albedo = 0.5f, le = 1.0f;
  const auto scene = emissive_box(albedo, le);
  RenderSettings s;
  s.max_depth = GetParam();
  s.spp = 64;
  for (MisHeuristic h : {MisHeuristic::Power, MisHeuristic::Balance}) {
    s.mis = h;
    const RenderResult r = render(PathTracer(), *scene, s);
    double expected = 0.0;
    const int k = s.max_depth < 0 ? 1000 : s.max_depth;
    for (int i = 0; i < k; ++i) expected += le * std::pow(albedo, float(i));
    const ImageStats st = stats_of(r.image);
    EXPECT_NEAR(st.mean, expected, 5.0 * st.standard_error + 0.002 * expected)
        << "max_depth " << s.max_depth << " heuristic " << to_string(h);
    EXPECT_EQ(r.invalid_samples, 0u);
  }
}

INSTANTIATE_TEST_SUITE_P(Depths, ClosedBoxTest, ::testing::Values(1, 2, 3, 5, -1));

TEST(DirectIntegrator, ClosedBoxGivesEmissionPlusOneBounce) {
  const auto scene = emissive_box(0.5f, 1.0f);
  RenderSettings s;
  s.spp = 64;
  const ImageStats st = stats_of(render(DirectIntegrator(), *scene, s).image);
  EXPECT_NEAR(st.mean, 1.5, 5.0 * st.standard_error + 0.003);
}

namespace {

// A white (albedo 1) convex sphere inside a constant environment: every bounce leaves to
// the sky, so the sphere has the sky's radiance (the white furnace).
std::unique_ptr<Scene> furnace(BsdfPtr bsdf, float sky) {
  SceneDescription d;
  d.source = "furnace";
  SphereDesc sphere;
  sphere.radius = 1.0f;
  sphere.material = add_material(d, std::move(bsdf));
  d.spheres.push_back(sphere);
  d.environment.kind = EnvironmentDesc::Kind::Constant;
  d.environment.radiance = Rgb(sky);
  d.camera = camera_at(Vec3(0, 0, -4), Vec3(0), 16);
  d.camera.fov_degrees = 20.0f;  // the sphere fills the view
  return Scene::build(std::move(d));
}

}  // namespace

TEST(WhiteFurnace, DiffuseSphereReturnsTheSkyRadiance) {
  const auto scene = furnace(make_lambertian(Rgb(1.0f)), 2.0f);
  RenderSettings s;
  s.spp = 32;
  for (const Integrator* integrator : std::initializer_list<const Integrator*>{new PathTracer, new DirectIntegrator}) {
    const RenderResult r = render(*integrator, *scene, s);
    const ImageStats st = stats_of(r.image);
    EXPECT_NEAR(st.mean, 2.0, 5.0 * st.standard_error + 0.004) << integrator->name();
    delete integrator;
  }
}

TEST(WhiteFurnace, GlassSphereIsInvisible) {
  // A smooth dielectric conserves energy; under a constant sky it must vanish (radiance
  // mode: the 1/eta^2 compression entering is undone leaving).
  const auto scene = furnace(make_dielectric(1.5f, 1.0f), 1.0f);
  RenderSettings s;
  s.spp = 32;
  s.max_depth = 64;
  const ImageStats st = stats_of(render(PathTracer(), *scene, s).image);
  EXPECT_NEAR(st.mean, 1.0, 5.0 * st.standard_error + 0.003);
}

TEST(ConstantSky, DiffusePlaneHasAlbedoTimesSky) {
  SceneDescription d;
  d.source = "plane";
  const int m = add_material(d, make_lambertian(Rgb(0.25f, 0.5f, 0.75f)));
  add_quad(d, Vec3(-100, 0, -100), Vec3(-100, 0, 100), Vec3(100, 0, 100), Vec3(100, 0, -100), m);
  d.environment.kind = EnvironmentDesc::Kind::Constant;
  d.environment.radiance = Rgb(1.0f);
  d.camera = camera_at(Vec3(0, 2, 0), Vec3(0.1f, 0, 0.1f), 16, Vec3(0, 0, 1));
  const auto scene = Scene::build(std::move(d));
  RenderSettings s;
  s.spp = 32;
  for (int c = 0; c < 3; ++c) {
    const double expected = 0.25 * (c + 1);
    for (const Integrator* integrator : std::initializer_list<const Integrator*>{new PathTracer, new DirectIntegrator}) {
      const ImageStats st = stats_of(render(*integrator, *scene, s).image, c);
      EXPECT_NEAR(st.mean, expected, 5.0 * st.standard_error + 0.002) << integrator->name();
      delete integrator;
    }
  }
}

namespace {

// A diffuse floor under a small square light facing down: only direct light exists.
std::unique_ptr<Scene> floor_and_light() {
  SceneDescription d;
  d.source = "floor-and-light";
  const int floor = add_material(d, make_lambertian(Rgb(0.7f)));
  const int black = add_material(d, make_lambertian(Rgb(0.0f)));
  add_quad(d, Vec3(-4, 0, -4), Vec3(-4, 0, 4), Vec3(4, 0, 4), Vec3(4, 0, -4), floor);
  add_quad(d, Vec3(-0.5f, 2, -0.5f), Vec3(0.5f, 2, -0.5f), Vec3(0.5f, 2, 0.5f), Vec3(-0.5f, 2, 0.5f), black,
           Rgb(10.0f));
  d.camera = camera_at(Vec3(0, 3, -5), Vec3(0, 0, 0), 24);
  return Scene::build(std::move(d));
}

double mse(const Image& a, const Image& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const Rgb d = a.pixels[i] - b.pixels[i];
    sum += glm::dot(d, d) / 3.0;
  }
  return sum / double(a.pixels.size());
}

}  // namespace

TEST(DirectOnlyScene, DirectAndPathTracerAgree) {
  const auto scene = floor_and_light();
  RenderSettings s;
  s.spp = 256;
  const Image direct = render(DirectIntegrator(), *scene, s).image;
  s.seed = 2;
  const Image pt = render(PathTracer(), *scene, s).image;
  const ImageStats a = stats_of(direct), b = stats_of(pt);
  EXPECT_GT(a.mean, 0.03);
  EXPECT_NEAR(a.mean, b.mean, 0.01 * a.mean);
  // Per pixel as well: the floor images agree up to noise.
  EXPECT_LT(mse(direct, pt), 0.02 * a.mean * a.mean);
}

TEST(DirectOnlyScene, FibonacciPointSetKeepsTheImageUnbiased) {
  const auto scene = floor_and_light();
  RenderSettings s;
  s.spp = 1024;
  const double reference = stats_of(render(DirectIntegrator(), *scene, s).image).mean;
  s.spp = 16;
  s.direct_samples = 16;
  s.direct_point_set = DirectPointSet::Fibonacci;
  const ImageStats fib = stats_of(render(DirectIntegrator(), *scene, s).image);
  EXPECT_NEAR(fib.mean, reference, 0.005 * reference);
}

TEST(DirectLightingEstimator, FibonacciPointSetReducesVarianceAtAPoint) {
  // At a fixed shading point (no pixel jitter) the randomised spherical Fibonacci set has
  // the same mean as independent sampling and clearly lower variance (about half here).
  const auto scene = floor_and_light();
  for (const Vec3 origin : {Vec3(0.3f, 1, 0.2f), Vec3(-1.5f, 1, 0.7f)}) {
    SurfaceHit hit;
    ASSERT_TRUE(scene->intersect(Ray{origin, Vec3(0, -1, 0)}, hit));
    double mean[2], variance[2];
    for (int fibonacci = 0; fibonacci < 2; ++fibonacci) {
      DirectLightingOptions options;
      options.samples = 16;
      options.point_set = fibonacci ? DirectPointSet::Fibonacci : DirectPointSet::Independent;
      double sum = 0.0, sum2 = 0.0;
      const int n = 20000;
      for (int i = 0; i < n; ++i) {
        Rng rng(5, uint64_t(i));
        const double v = estimate_direct_lighting(*scene, hit, Vec3(0, 1, 0), rng, options).y;
        sum += v;
        sum2 += v * v;
      }
      mean[fibonacci] = sum / n;
      variance[fibonacci] = sum2 / n - mean[fibonacci] * mean[fibonacci];
    }
    const double se = std::sqrt((variance[0] + variance[1]) / 20000.0);
    EXPECT_NEAR(mean[1], mean[0], 4.0 * se);
    EXPECT_LT(variance[1], 0.75 * variance[0]);
  }
}

TEST(Determinism, SameSeedSameBitsAtAnyThreadCount) {
  const auto scene = emissive_box(0.5f, 1.0f);
  RenderSettings s;
  s.spp = 8;
  s.threads = 1;
  const Image one = render(PathTracer(), *scene, s).image;
  s.threads = 2;
  const Image two = render(PathTracer(), *scene, s).image;
  s.seed = 99;
  const Image other = render(PathTracer(), *scene, s).image;
  EXPECT_EQ(0, std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Rgb)));
  EXPECT_NE(0, std::memcmp(one.pixels.data(), other.pixels.data(), one.pixels.size() * sizeof(Rgb)));
}
