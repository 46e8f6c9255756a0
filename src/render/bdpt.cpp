#include "emlt/render/bdpt.h"

#include "emlt/render/pass_schedule.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <filesystem>
#include <fmt/core.h>

#include "emlt/core/error.h"
#include "emlt/core/rng.h"
#include "emlt/path/connection.h"
#include "emlt/path/path_density.h"
#include "emlt/path/random_walk.h"
#include "emlt/render/splat_film.h"

namespace emlt {

namespace {

constexpr int kTileSize = 16;
// Samples per pass are bounded so the splat lists of one pass stay small (a few splats of
// 20 bytes per sample); the bound depends on the image only, so passes never depend on
// the thread count.
constexpr uint64_t kSamplesPerPass = uint64_t(1) << 18;

// Strategy images: paths of n = s + t vertices, n = 2 .. kMaxStrategyImageDepth + 1, and
// s = 0 .. n - 1, numbered n by n.
int strategy_image_index(int s, int t) {
  const int n = s + t;
  if (t < 1 || n < 2 || n - 1 > BidirectionalPathTracer::kMaxStrategyImageDepth) return -1;
  return (n - 1) * n / 2 - 1 + s;
}
int strategy_image_count() {
  const int n = BidirectionalPathTracer::kMaxStrategyImageDepth + 1;
  return n * (n + 1) / 2 - 1;
}

struct Tile {
  int x0, y0, x1, y1;
};

std::vector<Tile> make_tiles(int width, int height) {
  std::vector<Tile> tiles;
  for (int y = 0; y < height; y += kTileSize)
    for (int x = 0; x < width; x += kTileSize)
      tiles.push_back({x, y, std::min(x + kTileSize, width), std::min(y + kTileSize, height)});
  return tiles;
}

// Everything one pixel sample needs; the vectors are reused across samples of a tile.
struct SampleScratch {
  std::vector<PathVertex> light, camera;
  VertexDensity densities[kMaxPathVertices];
};

// One tile's output for a pass: its light-tracing splats and its dropped-value count.
struct TileOutput {
  SplatList splats;
  InvalidCounter invalid;
};

class BdptSampler {
 public:
  BdptSampler(const Scene& scene, const RenderSettings& settings, const BdptOptions& options,
              bool strategy_images)
      : scene_(scene), settings_(settings), options_(options), strategy_images_(strategy_images) {
    max_depth_ = settings.max_depth < 0 ? BidirectionalPathTracer::kUnlimitedDepth
                                        : std::min(settings.max_depth, kMaxPathVertices - 1);
    // A path of max_depth segments has max_depth + 1 vertices: s = 0 needs them all on the
    // camera side, t = 1 needs max_depth on the light side.
    camera_limits_ = {max_depth_ + 1, settings.rr_depth};
    light_limits_ = {max_depth_, settings.rr_depth};
  }

  // One sample at `raster`: camera-side contributions go to `pixel` (and the pixel's
  // strategy values), light-tracing splats to the tile's list.
  void sample(Rng& rng, const Vec2& raster, const Vec2& u_lens, SampleScratch& scratch,
              DVec3& pixel, DVec3* strategy_pixel, TileOutput& out) const {
    auto& camera = scratch.camera;
    auto& light = scratch.light;
    generate_camera_subpath(scene_, rng, raster, u_lens, camera_limits_, camera, &out.invalid);
    generate_light_subpath(scene_, rng, light_limits_, light, &out.invalid);

    for (int t = 1; t <= int(camera.size()); ++t) {
      if (options_.only_t >= 1 && t != options_.only_t) continue;
      for (int s = 0; s <= int(light.size()); ++s) {
        const int segments = s + t - 1;
        if (segments < 1) continue;
        if (segments > max_depth_) break;
        if (options_.only_s >= 0 && s != options_.only_s) continue;
        evaluate_strategy(rng, s, t, scratch, pixel, strategy_pixel, out);
      }
    }
  }

 private:
  void evaluate_strategy(Rng& rng, int s, int t, SampleScratch& scratch, DVec3& pixel,
                         DVec3* strategy_pixel, TileOutput& out) const {
    const auto& camera = scratch.camera;
    const auto& light = scratch.light;
    Rgb contribution(0.0f);
    PathVertex lens;  // the lens vertex sampled for t = 1
    std::span<const PathVertex> camera_side(camera);
    if (s == 0) {
      // The camera subpath found an emitter (or the sky) at its last vertex.
      const PathVertex& z = camera[size_t(t - 1)];
      if (!z.is_emitter()) return;
      contribution = z.throughput * vertex_factor(scene_, z, nullptr, &camera[size_t(t - 2)]);
    } else {
      const PathVertex& y = light[size_t(s - 1)];
      const PathVertex* y_previous = s >= 2 ? &light[size_t(s - 2)] : nullptr;
      if (t == 1) {
        const auto sampled = sample_camera_vertex(scene_, y, rng.uniform2());
        if (!sampled) return;
        lens = *sampled;
        camera_side = std::span<const PathVertex>(&lens, 1);
        contribution = y.throughput * connect_vertices(scene_, y_previous, y, lens, nullptr) *
                       lens.throughput;
      } else {
        const PathVertex& z = camera[size_t(t - 1)];
        contribution = y.throughput *
                       connect_vertices(scene_, y_previous, y, z, &camera[size_t(t - 2)]) *
                       z.throughput;
      }
    }
    if (is_black(contribution)) return;

    double weight = 1.0;
    if (options_.mis) {
      const std::span<VertexDensity> densities(scratch.densities, size_t(s + t));
      connection_densities(scene_, light, s, camera_side, t, densities);
      weight = mis_weight(densities, s, settings_.mis);
    }
    Rgb value = contribution * float(weight);
    if (!out.invalid.keep(value) || is_black(value)) return;

    const int strategy = strategy_images_ ? strategy_image_index(s, t) : -1;
    if (t == 1) {
      // Light tracing: the contribution lands in every pixel whose filter covers it.
      scene_.camera().filter().splat(lens.raster, [&](uint32_t target, float weight) {
        out.splats.add(target, value * weight, strategy);
      });
      return;
    }
    pixel += DVec3(value);
    if (strategy >= 0) strategy_pixel[strategy] += DVec3(value);
  }

  const Scene& scene_;
  const RenderSettings& settings_;
  const BdptOptions& options_;
  bool strategy_images_;
  int max_depth_ = 0;
  WalkLimits camera_limits_, light_limits_;
};

void write_strategy_images(const std::string& directory, int width, int height,
                           const std::vector<DVec3>& camera_sums, const SplatFilm& film,
                           double camera_scale, double splat_scale) {
  std::filesystem::create_directories(directory);
  const size_t pixels = size_t(width) * size_t(height);
  for (int n = 2; n <= BidirectionalPathTracer::kMaxStrategyImageDepth + 1; ++n) {
    for (int s = 0; s < n; ++s) {
      const int index = strategy_image_index(s, n - s);
      Image image(width, height);
      for (size_t p = 0; p < pixels; ++p)
        image.pixels[p] = Rgb(camera_sums[size_t(index) * pixels + p] * camera_scale +
                              film.layer(index)[p] * splat_scale);
      const std::string name = fmt::format("s{}_t{}.exr", s, n - s);
      write_image((std::filesystem::path(directory) / name).string(), image);
    }
  }
}

}  // namespace

RenderResult BidirectionalPathTracer::render(const Scene& scene, const RenderSettings& settings,
                                             ProgressReporter& progress) const {
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  const bool strategy_images = !settings.bdpt_strategies_dir.empty();
  const int strategies = strategy_images ? strategy_image_count() : 0;

  const std::vector<Tile> tiles = make_tiles(width, height);
  std::vector<DVec3> camera_sums(pixels, DVec3(0.0));
  std::vector<DVec3> strategy_sums(size_t(strategies) * pixels, DVec3(0.0));
  SplatFilm film(width, height, strategies);
  std::vector<TileOutput> outputs(tiles.size());
  const BdptSampler sampler(scene, settings, options_, strategy_images);

  // Camera-side estimates average over the pixel's samples. A splat carries W_e of the
  // whole film (camera.h), so the light-tracing image is scaled by pixels / light paths;
  // there is one light path per pixel sample.
  const auto average = [&](int samples) {
    Image image(width, height);
    const double camera_scale = samples > 0 ? 1.0 / samples : 0.0;
    const double light_paths = double(pixels) * double(samples);
    const double splat_scale = light_paths > 0.0 ? double(pixels) / light_paths : 0.0;
    for (uint64_t i = 0; i < pixels; ++i)
      image.pixels[i] = Rgb(camera_sums[i] * camera_scale + film.sums()[i] * splat_scale);
    return image;
  };

  const int threads = settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  // Passes are bounded so the splat lists stay small.
  const int bounded_pass = int(std::max<uint64_t>(1, kSamplesPerPass / std::max<uint64_t>(pixels, 1)));
  PassSchedule schedule(settings, bounded_pass);
  const bool timed = settings.time_limit_s > 0.0;
  progress.start("rendering", timed ? 0 : pixels * uint64_t(schedule.max_samples()), settings.time_limit_s);

  RenderResult result;
  while (schedule.more()) {
    const int first = schedule.pass_begin(), last = schedule.pass_end();
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& range) {
        SampleScratch scratch;
        std::vector<DVec3> strategy_pixel(static_cast<size_t>(strategies));
        for (size_t index = range.begin(); index < range.end(); ++index) {
          const Tile& tile = tiles[index];
          TileOutput& out = outputs[index];
          for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) {
              const uint64_t pixel = uint64_t(y) * uint64_t(width) + uint64_t(x);
              const uint64_t pixel_stream = derive_stream_seed(settings.seed, pixel);
              DVec3 sum(0.0);
              std::fill(strategy_pixel.begin(), strategy_pixel.end(), DVec3(0.0));
              for (int k = first; k < last; ++k) {
                // Same stream and first draws as the path tracer's pixel driver.
                Rng rng(pixel_stream, uint64_t(k));
                const Vec2 jitter = rng.uniform2();
                const Vec2 u_lens = rng.uniform2();
                sampler.sample(rng, camera.filter().sample(x, y, jitter), u_lens, scratch, sum,
                               strategy_pixel.data(), out);
              }
              camera_sums[pixel] += sum;
              for (int i = 0; i < strategies; ++i)
                strategy_sums[size_t(i) * pixels + pixel] += strategy_pixel[size_t(i)];
            }
          }
          progress.advance(uint64_t(tile.y1 - tile.y0) * uint64_t(tile.x1 - tile.x0) *
                           uint64_t(last - first));
        }
      });
    });
    // Splats are added in tile order: the same bits at any thread count.
    std::vector<SplatList> lists(outputs.size());
    for (size_t i = 0; i < outputs.size(); ++i) {
      lists[i].records.swap(outputs[i].splats.records);
      result.invalid_samples += outputs[i].invalid.count;
      outputs[i].invalid.count = 0;
    }
    film.add_in_order(lists);
    schedule.complete_pass(average);
  }
  schedule.finish(average);
  progress.finish();

  const int done = schedule.samples();
  result.seconds = schedule.seconds();
  result.samples_per_pixel = done;
  result.samples = pixels * uint64_t(done);
  result.image = average(done);
  const double camera_scale = done > 0 ? 1.0 / done : 0.0;
  const double splat_scale = done > 0 ? 1.0 / double(done) : 0.0;
  if (strategy_images)
    write_strategy_images(settings.bdpt_strategies_dir, width, height, strategy_sums, film,
                          camera_scale, splat_scale);
  return result;
}

}  // namespace emlt
