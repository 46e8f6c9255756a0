#include "support/mlt_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numeric>

#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/mlt/bootstrap.h"
#include "emlt/path/connection.h"
#include "emlt/scene/loaders/loader.h"
#include "mutations/perturbation_common.h"
#include "support/test_support.h"

namespace emlt::test {

namespace {
double luminance(const DVec3& c) {
  return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}
}  // namespace

std::unique_ptr<Scene> shipped_scene(const std::string& name, int size) {
  SceneDescription desc =
      load_scene_description(test::source_path("scenes/" + name + "/scene.json"), {});
  desc.camera.width = desc.camera.height = size;
  return Scene::build(std::move(desc));
}

std::vector<Path> bootstrap_paths(const Scene& scene, int count, int max_edges) {
  BootstrapParams params;
  params.seed = 5;
  params.samples = 20000;
  params.min_edges = 3;
  params.max_edges = max_edges;
  params.threads = 1;
  const Bootstrap bootstrap = run_bootstrap(scene, params);
  std::vector<Path> paths;
  Rng rng(3, 3);
  for (int i = 0; i < count * 4 && int(paths.size()) < count; ++i) {
    const auto path = rebuild_candidate(
        scene, params, bootstrap.candidates[bootstrap.choose(rng.uniform_double())]);
    if (path && path_luminance(scene, *path) > 0.0) paths.push_back(*path);
  }
  return paths;
}

Image render(const Integrator& integrator, const Scene& scene, RenderSettings settings) {
  settings.progress = false;
  ProgressReporter quiet(false);
  return integrator.render(scene, settings, quiet).image;
}

RenderSettings base_settings() {
  RenderSettings s;
  s.max_depth = 6;
  s.threads = 2;
  s.seed = 7;
  return s;
}

Image bdpt_reference(const Scene& scene, int spp) {
  RenderSettings s = base_settings();
  s.spp = spp;
  return render(BidirectionalPathTracer(), scene, s);
}

Image mlt_image(const Scene& scene, const std::string& mix, double mpp, MltStatistics* stats,
                GamltVariant variant) {
  RenderSettings s = base_settings();
  s.gamlt_field_cone = variant.field_cone;
  s.gamlt_cone_cells = variant.cone_cells;
  s.gamlt_delayed_acceptance = variant.delayed_acceptance;
  s.mutations = mix;
  s.mutations_per_pixel = mpp;
  s.chains = 64;
  s.bootstrap_samples = 50000;
  s.direct_spp = 256;
  const MltIntegrator mlt;
  Image image = render(mlt, scene, s);
  if (stats) *stats = mlt.statistics();
  return image;
}

namespace {

// Luminance sums over blocks x blocks tiles, row by row.
std::vector<double> tile_sums(const Image& image, int blocks) {
  const int tile = image.width / blocks;
  std::vector<double> sums;
  for (int by = 0; by < blocks; ++by)
    for (int bx = 0; bx < blocks; ++bx) {
      double sum = 0.0;
      for (int y = by * tile; y < (by + 1) * tile; ++y)
        for (int x = bx * tile; x < (bx + 1) * tile; ++x) sum += luminance(DVec3(image.at(x, y)));
      sums.push_back(sum);
    }
  return sums;
}

}  // namespace

TileDeviation tile_deviation(const Image& image, const Image& reference, int blocks) {
  const std::vector<double> sums = tile_sums(image, blocks),
                            reference_sums = tile_sums(reference, blocks);
  TileDeviation d;
  d.scale = std::accumulate(sums.begin(), sums.end(), 0.0) /
            std::accumulate(reference_sums.begin(), reference_sums.end(), 0.0);
  for (size_t i = 0; i < sums.size(); ++i)
    d.worst = std::max(d.worst, std::abs(sums[i] / (reference_sums[i] * d.scale) - 1.0));
  return d;
}

void expect_converged_to(const Image& image, const Image& reference, int blocks,
                         double tile_tolerance, double total_tolerance) {
  const std::vector<double> sums = tile_sums(image, blocks),
                            reference_sums = tile_sums(reference, blocks);
  const TileDeviation d = tile_deviation(image, reference, blocks);
  EXPECT_NEAR(d.scale, 1.0, total_tolerance);
  for (size_t i = 0; i < sums.size(); ++i)
    EXPECT_NEAR(sums[i] / (reference_sums[i] * d.scale), 1.0, tile_tolerance)
        << "tile (" << i % size_t(blocks) << ", " << i / size_t(blocks) << ")";
  std::printf("[ info     ] total ratio %.4f, worst tile deviation %.4f\n", d.scale, d.worst);
}

Path floor_mirror_light_path(const Scene& scene, const Vec2& raster, const Vec3& up) {
  const Camera& camera = scene.camera();
  const Ray ray = camera.generate_ray(raster, Vec2(0.5f));
  SurfaceHit seen, on_mirror, lit, on_light;
  EXPECT_TRUE(scene.intersect(ray, seen));
  EXPECT_TRUE(scene.intersect(spawn_ray(seen.position, seen.geometric_normal, up), on_mirror));
  const Vec3 down = reflect_about(-up, on_mirror.geometric_normal);
  EXPECT_TRUE(
      scene.intersect(spawn_ray(on_mirror.position, on_mirror.geometric_normal, down), lit));
  EXPECT_TRUE(
      scene.intersect(spawn_ray(lit.position, lit.geometric_normal, Vec3(0, 1, 0)), on_light));
  return path_through_mirror(scene, {on_light, lit, on_mirror, seen}, ray.origin, raster, 2);
}

Path path_through_mirror(const Scene& scene, const std::vector<SurfaceHit>& hits, const Vec3& lens,
                         const Vec2& raster, int mirror) {
  Path path;
  for (const SurfaceHit& hit : hits) path.vertices.push_back(make_surface_vertex(hit));
  path.vertices.push_back(make_camera_vertex(scene, lens, raster));
  auto& v = path.vertices;
  const size_t m = size_t(mirror);
  EXPECT_TRUE(
      perturbation::fill_delta_record(v[m], v[m + 1], v[m - 1], TransportMode::Radiance, false));
  path.type = compute_path_type(path.vertices);
  recompute_densities(scene, path);
  return path;
}

double log_floor_area_per_nu(const Path& path) {
  const auto& v = path.vertices;
  const double d32 = glm::length(DVec3(v[3].position) - DVec3(v[2].position));
  const double d21 = glm::length(DVec3(v[2].position) - DVec3(v[1].position));
  const double cos2 =
      std::abs(glm::dot(DVec3(v[2].normal), perturbation::precise_direction(v[2], v[3])));
  return std::log(cos2) + 2.0 * (std::log(d32 + d21) - std::log(d32) - std::log(d21));
}

double share_of(const MltStatistics& stats, const std::string& name) {
  uint64_t total = 0, mine = 0;
  for (size_t i = 0; i < stats.strategies.size(); ++i) {
    total += stats.strategies[i].proposed;
    if (stats.strategy_names[i] == name) mine = stats.strategies[i].accepted;
  }
  return total ? double(mine) / double(total) : 0.0;
}

Path light_floor_eye_path(const Scene& scene, const Vec2& raster) {
  const Camera& camera = scene.camera();
  const Ray ray = camera.generate_ray(raster, Vec2(0.5f));
  SurfaceHit floor_hit, light_hit;
  EXPECT_TRUE(scene.intersect(ray, floor_hit));
  EXPECT_TRUE(scene.intersect(Ray{Vec3(0.0f, 0.01f, 0.0f), Vec3(0, 1, 0)}, light_hit));
  Path path;
  path.vertices.push_back(make_surface_vertex(light_hit));
  path.vertices.push_back(make_surface_vertex(floor_hit));
  path.vertices.push_back(make_camera_vertex(scene, ray.origin, raster));
  path.type = compute_path_type(path.vertices);
  recompute_densities(scene, path);
  return path;
}

double landing_density(const Mutation& mutation, const Path& x, int moved, const Vec3& target,
                       float radius, int proposals, const MutationContext& ctx, uint64_t seed,
                       int* hits_out) {
  Rng rng(seed, 7);
  int hits = 0;
  for (int i = 0; i < proposals; ++i) {
    const auto y = mutation.propose(x, rng, ctx);
    if (y && glm::length(y->path.vertices[size_t(moved)].position - target) < radius) ++hits;
  }
  EXPECT_GT(hits, 800) << "too few landings for a density estimate";
  if (hits_out) *hits_out = hits;
  return double(hits) / (double(proposals) * double(kPi) * double(radius) * double(radius));
}

}  // namespace emlt::test
