// Bidirectional path tracing against exact answers and against the path tracer. Seeds are
// fixed, so every threshold below was checked to hold with margin (noise is a few times
// smaller than the threshold) while a wrong MIS weight or density visibly breaks it.
#include "emlt/integrators/bdpt.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "emlt/integrators/path_tracer.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "support/image_checks.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

void add_quad(SceneDescription& d, Vec3 a, Vec3 b, Vec3 c, Vec3 e, int material, Rgb emission = Rgb(0)) {
  MeshDesc m;
  m.name = "quad";
  m.positions = {a, b, c, e};
  m.indices = {0, 1, 2, 0, 2, 3};
  m.material = material;
  m.emission = emission;
  d.meshes.push_back(m);
}

// The closed emissive box of integrator_test.cpp: every face emits le and reflects with
// albedo a, so paths of exactly k segments carry le * a^(k-1) everywhere.
std::unique_ptr<Scene> emissive_box(float albedo, float le, int size = 16) {
  SceneDescription d;
  d.source = "emissive-box";
  d.materials.push_back({"wall", make_lambertian(Rgb(albedo))});
  const Rgb e(le);
  const Vec3 p[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                     {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  add_quad(d, p[0], p[1], p[2], p[3], 0, e);
  add_quad(d, p[5], p[4], p[7], p[6], 0, e);
  add_quad(d, p[4], p[0], p[3], p[7], 0, e);
  add_quad(d, p[1], p[5], p[6], p[2], 0, e);
  add_quad(d, p[4], p[5], p[1], p[0], 0, e);
  add_quad(d, p[3], p[2], p[6], p[7], 0, e);
  d.camera.to_world = look_at_matrix(Vec3(0.1f, 0.2f, -0.5f), Vec3(0.3f, -0.2f, 1.0f), Vec3(0, 1, 0));
  d.camera.fov_degrees = 60.0f;
  d.camera.width = d.camera.height = size;
  return Scene::build(std::move(d));
}

// The inside of a closed, tessellated sphere that emits le and reflects with albedo a: the
// same exact answer as the box, but inside a sphere G = cos cos / d^2 is nearly the
// constant 1/(4 R^2), so even unweighted connection strategies have light tails (in the
// box, G's 1/d^2 at the edges gives them near-infinite variance).
std::unique_ptr<Scene> emissive_sphere(float albedo, float le, int size = 16) {
  SceneDescription d;
  d.source = "emissive-sphere";
  d.materials.push_back({"wall", make_lambertian(Rgb(albedo))});
  MeshDesc m;
  m.name = "sphere";
  m.material = 0;
  m.emission = Rgb(le);
  const int rings = 24, segments = 48;
  for (int i = 0; i <= rings; ++i) {
    const float theta = kPi * float(i) / float(rings);
    for (int j = 0; j < segments; ++j) {
      const float phi = kTwoPi * float(j) / float(segments);
      m.positions.push_back(Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
    }
  }
  const auto index = [&](int i, int j) { return uint32_t(i * segments + (j % segments)); };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      // Wound so the normals point inwards.
      if (i > 0) m.indices.insert(m.indices.end(), {index(i, j), index(i + 1, j), index(i, j + 1)});
      if (i + 1 < rings)
        m.indices.insert(m.indices.end(), {index(i, j + 1), index(i + 1, j), index(i + 1, j + 1)});
    }
  }
  d.meshes.push_back(m);
  d.camera.to_world = look_at_matrix(Vec3(0.1f, 0.2f, -0.3f), Vec3(0.3f, -0.2f, 1.0f), Vec3(0, 1, 0));
  d.camera.fov_degrees = 60.0f;
  d.camera.width = d.camera.height = size;
  return Scene::build(std::move(d));
}

std::unique_ptr<Scene> shipped_scene(const std::string& name, int width, int height) {
  SceneDescription desc = load_scene_description(test::source_path("scenes/" + name + "/scene.json"), {});
  desc.camera.width = width;
  desc.camera.height = height;
  return Scene::build(std::move(desc));
}

RenderResult render(const Integrator& integrator, const Scene& scene, RenderSettings s) {
  s.progress = false;
  ProgressReporter progress(false);
  return integrator.render(scene, s, progress);
}

double channel_mean(const Image& image, int channel) {
  double sum = 0.0;
  for (const Rgb& p : image.pixels) sum += p[channel];
  return sum / double(image.pixels.size());
}

double mean(const Image& image) {
  return (channel_mean(image, 0) + channel_mean(image, 1) + channel_mean(image, 2)) / 3.0;
}

double exact_box_radiance(float albedo, float le, int max_depth) {
  double expected = 0.0;
  const int k = max_depth < 0 ? 1000 : max_depth;
  for (int i = 0; i < k; ++i) expected += le * std::pow(double(albedo), double(i));
  return expected;
}

}  // namespace

// --- Exact answers in the closed emissive box ---------------------------------------

class BdptClosedBox : public ::testing::TestWithParam<int> {};

TEST_P(BdptClosedBox, MatchesGeometricSeriesWithBothHeuristics) {
  const auto scene = emissive_box(0.5f, 1.0f);
  RenderSettings s;
  s.max_depth = GetParam();
  s.spp = 32;
  for (MisHeuristic h : {MisHeuristic::Power, MisHeuristic::Balance}) {
    s.mis = h;
    const RenderResult r = render(BidirectionalPathTracer(), *scene, s);
    const double expected = exact_box_radiance(0.5f, 1.0f, s.max_depth);
    EXPECT_NEAR(channel_mean(r.image, 1), expected, 0.01 * expected)
        << "max_depth " << s.max_depth << " heuristic " << to_string(h);
    EXPECT_EQ(r.invalid_samples, 0u);
  }
}

INSTANTIATE_TEST_SUITE_P(Depths, BdptClosedBox, ::testing::Values(1, 2, 3, 5, -1));

// Each strategy alone, without MIS weights, estimates exactly the light of its own path
// length: le * a^(k-1) for k = s + t - 1 segments.
TEST(BdptStrategies, EveryUnweightedStrategyIsUnbiasedForItsPathLength) {
  const float albedo = 0.5f, le = 1.0f;
  const auto scene = emissive_sphere(albedo, le);
  for (int k = 1; k <= 4; ++k) {
    for (int s = 0; s <= k; ++s) {
      const int t = k + 1 - s;
      BdptOptions options;
      options.mis = false;
      options.only_s = s;
      options.only_t = t;
      RenderSettings settings;
      settings.max_depth = k;
      // Light tracing's splats scatter over the film: it needs more samples per pixel.
      settings.spp = t == 1 ? 1024 : 64;
      settings.seed = uint64_t(10 * k + s);
      const RenderResult r = render(BidirectionalPathTracer(options), *scene, settings);
      const double expected = le * std::pow(double(albedo), double(k - 1));
      EXPECT_NEAR(channel_mean(r.image, 1), expected, (t == 1 ? 0.03 : 0.02) * expected)
          << "s=" << s << " t=" << t;
    }
  }
}

// The same on the Cornell box, against the path tracer restricted to 3 segments: with one
// seed, PT(max_depth 3) - PT(max_depth 2) holds exactly the 3-segment paths of the same
// random walks.
TEST(BdptStrategies, EveryUnweightedStrategyMatchesPathTracerOfThatLengthOnCornellBox) {
  const auto scene = shipped_scene("cornell-box", 16, 16);
  RenderSettings settings;
  settings.spp = 512;
  settings.max_depth = 3;
  const double up_to_3 = mean(render(PathTracer(), *scene, settings).image);
  settings.max_depth = 2;
  const double up_to_2 = mean(render(PathTracer(), *scene, settings).image);
  const double length_3 = up_to_3 - up_to_2;
  ASSERT_GT(length_3, 0.01);
  settings.max_depth = 3;
  for (int s = 0; s <= 3; ++s) {
    BdptOptions options;
    options.mis = false;
    options.only_s = s;
    options.only_t = 4 - s;
    settings.seed = uint64_t(100 + s);
    settings.spp = s == 0 ? 2048 : 512;  // hitting the small light is the noisiest strategy
    const double value = mean(render(BidirectionalPathTracer(options), *scene, settings).image);
    EXPECT_NEAR(value, length_3, 0.04 * length_3) << "s=" << s << " t=" << 4 - s;
  }
}

// --- Light tracing alone ------------------------------------------------------------

TEST(BdptLightTracing, AloneMatchesPathTracerOnCornellBox) {
  const auto scene = shipped_scene("cornell-box", 16, 16);
  RenderSettings settings;
  settings.spp = 512;
  settings.max_depth = 4;
  const Image reference = render(PathTracer(), *scene, settings).image;
  BdptOptions options;
  options.mis = false;
  options.only_t = 1;  // every s: light tracing of every path length
  settings.seed = 7;
  const Image light_traced = render(BidirectionalPathTracer(options), *scene, settings).image;
  EXPECT_NEAR(mean(light_traced), mean(reference), 0.02 * mean(reference));
  EXPECT_LT(test::worst_block_error(reference, light_traced, 8), 0.05);
}

// --- BDPT against the path tracer on the shipped scenes ------------------------------

struct SceneCase {
  const char* name;
  int width, height, spp;
  double mean_tolerance, block_tolerance;
};

class BdptMatchesPathTracer : public ::testing::TestWithParam<SceneCase> {};

TEST_P(BdptMatchesPathTracer, OnShippedScene) {
  const SceneCase c = GetParam();
  std::string folder = c.name;
  std::replace(folder.begin(), folder.end(), '_', '-');
  const auto scene = shipped_scene(folder, c.width, c.height);
  RenderSettings settings;
  settings.spp = c.spp * 16;  // the reference gets the cheaper integrator's extra samples
  const Image reference = render(PathTracer(), *scene, settings).image;
  settings.spp = c.spp;
  settings.seed = 11;
  const RenderResult r = render(BidirectionalPathTracer(), *scene, settings);
  EXPECT_EQ(r.invalid_samples, 0u);
  EXPECT_NEAR(mean(r.image), mean(reference), c.mean_tolerance * mean(reference)) << c.name;
  EXPECT_LT(test::worst_block_error(reference, r.image, 8), c.block_tolerance) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, BdptMatchesPathTracer,
    ::testing::Values(SceneCase{"cornell_box", 16, 16, 256, 0.015, 0.05},
                      SceneCase{"cornell_glass", 16, 16, 256, 0.015, 0.06},
                      SceneCase{"env_sky", 24, 16, 256, 0.015, 0.05}),
    [](const auto& info) { return std::string(info.param.name); });

// --- Determinism and strategy images -------------------------------------------------

TEST(BdptDeterminism, SameSeedSameBitsAtAnyThreadCount) {
  const auto scene = shipped_scene("cornell-box", 24, 24);
  RenderSettings s;
  s.spp = 4;
  s.threads = 1;
  const Image one = render(BidirectionalPathTracer(), *scene, s).image;
  s.threads = 2;
  const Image two = render(BidirectionalPathTracer(), *scene, s).image;
  s.seed = 99;
  const Image other = render(BidirectionalPathTracer(), *scene, s).image;
  EXPECT_EQ(0, std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Rgb)));
  EXPECT_NE(0, std::memcmp(one.pixels.data(), other.pixels.data(), one.pixels.size() * sizeof(Rgb)));
}

TEST(BdptStrategyImages, AreWrittenAndSumToTheImage) {
  const auto scene = shipped_scene("cornell-box", 16, 16);
  const auto directory = test::scratch_dir("bdpt_strategies");
  RenderSettings s;
  s.spp = 8;
  s.max_depth = BidirectionalPathTracer::kMaxStrategyImageDepth;
  s.bdpt_strategies_dir = directory.string();
  const Image image = render(BidirectionalPathTracer(), *scene, s).image;
  Image sum(image.width, image.height);
  int files = 0;
  for (int n = 2; n <= s.max_depth + 1; ++n) {
    for (int t = 1; t <= n; ++t) {
      const auto file = directory / fmt::format("s{}_t{}.exr", n - t, t);
      ASSERT_TRUE(std::filesystem::exists(file)) << file;
      const Image strategy = read_image(file.string());
      for (size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += strategy.pixels[i];
      ++files;
    }
  }
  EXPECT_EQ(files, 20);
  EXPECT_NEAR(mean(sum), mean(image), 1e-4 * mean(image));
  // Light tracing (t = 1) carries a visible share of the light in this scene.
  const Image light_traced = read_image((directory / "s2_t1.exr").string());
  EXPECT_GT(mean(light_traced), 0.0);
}
