#include "emlt/render/bdpt.h"

#include "emlt/render/pass_schedule.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <fmt/core.h>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/rng.h"
#include "emlt/path/connection.h"
#include "emlt/path/path_density.h"
#include "emlt/path/random_walk.h"
#include "emlt/render/interruption.h"
#include "emlt/render/pixel_renderer.h"
#include "emlt/render/render_control.h"
#include "emlt/render/snapshot.h"
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
  PathVertices light, camera;
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
    camera_limits_ = {max_depth_ + 1, subpath_rr_depth(settings.rr_depth)};
    light_limits_ = {max_depth_, subpath_rr_depth(settings.rr_depth)};
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
        if (segments < settings_.shortest_path()) continue;
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
    // The lens vertex sampled for t = 1 (empty otherwise: most strategies need none).
    std::optional<PathVertex> lens;
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
        lens = sample_camera_vertex(scene_, y, rng.uniform2());
        if (!lens) return;
        camera_side = std::span<const PathVertex>(&*lens, 1);
        contribution = y.throughput * connect_vertices(scene_, y_previous, y, *lens, nullptr) *
                       lens->throughput;
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
      scene_.camera().filter().splat(lens->raster, [&](uint32_t target, float weight) {
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
                           const std::vector<int32_t>& counts, double splat_scale) {
  std::filesystem::create_directories(directory);
  const size_t pixels = size_t(width) * size_t(height);
  for (int n = 2; n <= BidirectionalPathTracer::kMaxStrategyImageDepth + 1; ++n) {
    for (int s = 0; s < n; ++s) {
      const int index = strategy_image_index(s, n - s);
      Image image(width, height);
      for (size_t p = 0; p < pixels; ++p) {
        const double camera_scale = counts[p] > 0 ? 1.0 / counts[p] : 0.0;
        image.pixels[p] = Rgb(camera_sums[size_t(index) * pixels + p] * camera_scale +
                              film.layer(index)[p] * splat_scale);
      }
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
  // Camera-side sums and sample counts per pixel, as the pixel driver keeps them.
  PixelRenderState state;
  std::vector<DVec3> strategy_sums(size_t(strategies) * pixels, DVec3(0.0));
  SplatFilm film(width, height, strategies);
  // The splats of the pass under way, added to the film in tile order when it completes.
  std::vector<TileOutput> outputs(tiles.size());
  const BdptSampler sampler(scene, settings, options_, strategy_images);

  RenderControl* control = settings.control;
  const auto save = [&](StateWriter& out) {
    state.save(out);
    out.put_vector(strategy_sums);
    film.save(out);
    for (const TileOutput& tile : outputs) {
      out.put_vector(tile.splats.records);
      out.put(tile.invalid.count);
    }
  };
  if (control && !control->resume_state().empty()) {
    StateReader in(control->resume_state());
    state.load(in, width, height);
    strategy_sums = in.get_vector<DVec3>(size_t(strategies) * pixels);
    film.load(in);
    for (TileOutput& tile : outputs) {
      // A tile makes a few splats per sample; kSamplesPerPass bounds a pass's samples.
      tile.splats.records = in.get_vector_up_to<SplatRecord>(64 * kSamplesPerPass);
      for (const SplatRecord& r : tile.splats.records)
        if (r.pixel >= pixels || r.layer >= strategies)
          throw StateError("a saved splat lies outside the image");
      tile.invalid.count = in.get<uint64_t>();
    }
    in.expect_end();
  } else {
    state.sums.assign(pixels, DVec3(0.0));
    state.counts.assign(pixels, 0);
  }
  // Under MPI each rank renders the tiles of its rows (owns_row), and rank 0 adds every
  // rank's splats to the film in tile order.
  const auto owns_tile = [&](size_t index) { return owns_row(tiles[index].y0); };
  const auto merge_pass_splats = [&] {
    std::vector<SplatList> lists(outputs.size());
    if (cluster::size() == 1) {
      for (size_t i = 0; i < outputs.size(); ++i) lists[i].records.swap(outputs[i].splats.records);
    } else {
      StateWriter mine;
      for (size_t i = 0; i < outputs.size(); ++i) {
        if (!owns_tile(i)) continue;
        mine.put<uint64_t>(i);
        mine.put_vector(outputs[i].splats.records);
        outputs[i].splats.records.clear();
      }
      for (const std::string_view part : cluster::gather_to_root(mine.data())) {
        StateReader in(part);
        while (in.remaining() > 0) {
          const uint64_t i = in.get<uint64_t>();
          lists.at(i).records = in.get_vector_up_to<SplatRecord>(UINT64_MAX / sizeof(SplatRecord));
        }
      }
    }
    for (TileOutput& out : outputs) {
      state.invalid += out.invalid.count;
      out.invalid.count = 0;
    }
    film.add_in_order(lists);
  };

  // Camera-side estimates average over the pixel's samples. A splat carries W_e of the
  // whole film (camera.h), so the light-tracing image is scaled by pixels / light paths;
  // there is one light path per pixel sample. Complete on rank 0.
  uint64_t light_paths = 0;
  const auto image_now = [&] {
    const PixelRenderState::Totals totals = state.totals();
    light_paths = 0;
    for (const int32_t c : totals.counts) light_paths += uint64_t(c);
    Image image(width, height);
    const double splat_scale = light_paths > 0 ? double(pixels) / double(light_paths) : 0.0;
    for (uint64_t i = 0; i < pixels; ++i) {
      const double camera_scale = totals.counts[i] > 0 ? 1.0 / totals.counts[i] : 0.0;
      const DVec3 sum(totals.sums[3 * i], totals.sums[3 * i + 1], totals.sums[3 * i + 2]);
      image.pixels[i] = Rgb(sum * camera_scale + film.sums()[i] * splat_scale);
    }
    return image;
  };
  const auto average = [&](int) { return image_now(); };

  const int threads = settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  // Passes are bounded so the splat lists stay small.
  const int bounded_pass = int(std::max<uint64_t>(1, kSamplesPerPass / std::max<uint64_t>(pixels, 1)));
  PassSchedule schedule(settings, bounded_pass);
  if (state.resumed) schedule.restore(state.schedule);
  const bool timed = settings.time_limit_s > 0.0;
  progress.start("rendering", timed ? 0 : pixels * uint64_t(schedule.max_samples()), settings.time_limit_s);
  progress.advance(pixels * uint64_t(schedule.samples()));

  RenderResult result;
  bool mid_pass = state.schedule.pass_end > 0 && state.resumed;
  while (schedule.more()) {
    const int first = schedule.pass_begin(), last = schedule.pass_end();
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& range) {
        SampleScratch scratch;
        std::vector<DVec3> strategy_pixel(static_cast<size_t>(strategies));
        for (size_t index = range.begin(); index < range.end(); ++index) {
          if (!owns_tile(index)) continue;
          const Tile& tile = tiles[index];
          TileOutput& out = outputs[index];
          uint64_t tile_samples = 0;
          for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) {
              const uint64_t pixel = uint64_t(y) * uint64_t(width) + uint64_t(x);
              int k = std::max(first, int(state.counts[pixel]));
              if (k >= last || interruption::requested()) continue;
              const uint64_t pixel_stream = derive_stream_seed(settings.seed, pixel);
              // Each sample adds to the pixel's sums in sample order, whatever the passes.
              DVec3 sum = state.sums[pixel];
              for (int i = 0; i < strategies; ++i)
                strategy_pixel[size_t(i)] = strategy_sums[size_t(i) * pixels + pixel];
              const int begin = k;
              for (; k < last && !interruption::requested(); ++k) {
                // Same stream and first draws as the path tracer's pixel driver.
                Rng rng(pixel_stream, uint64_t(k));
                const Vec2 jitter = rng.uniform2();
                const Vec2 u_lens = rng.uniform2();
                sampler.sample(rng, camera.filter().sample(x, y, jitter), u_lens, scratch, sum,
                               strategy_pixel.data(), out);
              }
              state.sums[pixel] = sum;
              state.counts[pixel] = k;
              for (int i = 0; i < strategies; ++i)
                strategy_sums[size_t(i) * pixels + pixel] = strategy_pixel[size_t(i)];
              tile_samples += uint64_t(k - begin);
              interruption::poll(uint64_t(k - begin));
            }
          }
          progress.advance(tile_samples);
        }
      });
    });
    const bool incomplete = state.behind(last, width);
    const interruption::Decision decision = interruption::agree(incomplete);
    mid_pass = decision.incomplete;
    if (!mid_pass) {
      // Splats are added in tile order: the same bits at any thread and rank count.
      merge_pass_splats();
      schedule.complete_pass(average);
    }
    if (decision.pause()) {
      state.schedule = schedule.save(mid_pass);
      RenderControl::pause(control, save);
      if (decision.stop && (mid_pass || schedule.more())) {
        result.interrupted = true;
        break;
      }
    }
  }
  state.schedule = schedule.save(mid_pass);
  if (!result.interrupted) {
    schedule.finish(average);
    RenderControl::finish(control, save);
  } else {
    // The image of a stop inside a pass includes that pass's splats so far.
    merge_pass_splats();
  }
  progress.finish();

  result.image = image_now();
  std::vector<uint64_t> invalid = {state.invalid};
  cluster::sum_to_root(invalid);
  result.seconds = schedule.seconds();
  result.samples_per_pixel = schedule.samples();
  result.samples = light_paths;
  result.per_pixel = pixels > 0 ? double(light_paths) / double(pixels) : 0.0;
  result.invalid_samples = invalid[0];
  if (result.interrupted && settings.snapshots)
    settings.snapshots->snapshot(result.per_pixel, result.seconds, result.image, {});
  if (strategy_images) {
    std::vector<double> strategy_totals(3 * strategy_sums.size());
    for (size_t i = 0; i < strategy_sums.size(); ++i)
      for (int c = 0; c < 3; ++c) strategy_totals[3 * i + size_t(c)] = strategy_sums[i][c];
    cluster::sum_to_root(strategy_totals);
    const PixelRenderState::Totals totals = state.totals();
    if (cluster::is_root()) {
      for (size_t i = 0; i < strategy_sums.size(); ++i)
        strategy_sums[i] = DVec3(strategy_totals[3 * i], strategy_totals[3 * i + 1],
                                 strategy_totals[3 * i + 2]);
      write_strategy_images(settings.bdpt_strategies_dir, width, height, strategy_sums, film,
                            totals.counts,
                            light_paths > 0 ? double(pixels) / double(light_paths) : 0.0);
    }
  }
  return result;
}

}  // namespace emlt
