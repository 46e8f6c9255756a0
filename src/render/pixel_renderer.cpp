#include "emlt/render/pixel_renderer.h"

#include "emlt/render/snapshot.h"

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>

namespace emlt {

namespace {

constexpr int kTileSize = 16;

// Samples [first, last) of every pixel, added into `sums`.
uint64_t render_pass(const Scene& scene, const RenderSettings& settings,
                     ProgressReporter& progress, const RadianceEstimator& radiance,
                     int first, int last, std::vector<DVec3>& sums) {
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  tbb::combinable<uint64_t> invalid([] { return uint64_t(0); });
  tbb::parallel_for(
      tbb::blocked_range2d<int>(0, height, kTileSize, 0, width, kTileSize),
      [&](const tbb::blocked_range2d<int>& tile) {
        uint64_t& tile_invalid = invalid.local();
        for (int y = tile.rows().begin(); y < tile.rows().end(); ++y) {
          for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) {
            const uint64_t pixel = uint64_t(y) * uint64_t(width) + uint64_t(x);
            const uint64_t pixel_stream = derive_stream_seed(settings.seed, pixel);
            DVec3 sum(0.0);
            for (int k = first; k < last; ++k) {
              Rng rng(pixel_stream, uint64_t(k));
              const Vec2 jitter = rng.uniform2();
              const Vec2 u_lens = rng.uniform2();
              const Ray ray = camera.generate_ray(Vec2(float(x), float(y)) + jitter, u_lens);
              const Rgb value = radiance(ray, rng);
              if (is_finite(value) && value.x >= 0.0f && value.y >= 0.0f && value.z >= 0.0f)
                sum += DVec3(value);
              else
                ++tile_invalid;
            }
            sums[pixel] += sum;
          }
        }
        progress.advance(uint64_t(tile.rows().size()) * tile.cols().size() * uint64_t(last - first));
      });
  return invalid.combine(std::plus<uint64_t>());
}

}  // namespace

RenderResult render_pixels(const Scene& scene, const RenderSettings& settings,
                           ProgressReporter& progress, const RadianceEstimator& radiance) {
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  const bool timed = settings.time_limit_s > 0.0;
  // A time budget with no explicit sample cap runs until the time is up.
  const int max_spp = timed && settings.spp <= 0 ? std::numeric_limits<int>::max()
                                                 : std::max(settings.spp, 1);
  std::vector<DVec3> sums(pixels, DVec3(0.0));

  const int threads = settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  progress.start("rendering", timed ? 0 : pixels * uint64_t(max_spp), settings.time_limit_s);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };

  const auto average = [&](int samples) {
    Image image(width, height);
    const double scale = samples > 0 ? 1.0 / samples : 0.0;
    for (uint64_t i = 0; i < pixels; ++i) image.pixels[i] = Rgb(sums[i] * scale);
    return image;
  };
  double snapshot_seconds = 0.0;  // time spent in snapshots, not rendering
  const auto take_snapshot = [&](int samples) {
    const auto begin = std::chrono::steady_clock::now();
    settings.snapshots->snapshot(samples, elapsed() - snapshot_seconds, average(samples), {});
    snapshot_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  };

  RenderResult result;
  int done = 0, pass_spp = timed ? 1 : max_spp;
  while (done < max_spp) {
    // Passes always end at power-of-two sample counts (checkpoints), so a convergence log
    // changes nothing about how the samples are summed.
    const int last = int(std::min<uint64_t>(uint64_t(done + std::min(pass_spp, max_spp - done)),
                                            next_checkpoint(uint64_t(done))));
    arena.execute([&] {
      result.invalid_samples += render_pass(scene, settings, progress, radiance, done, last, sums);
    });
    done = last;
    if (settings.snapshots && is_checkpoint(uint64_t(done))) take_snapshot(done);
    if (!timed) continue;
    const double used = elapsed() - snapshot_seconds, left = settings.time_limit_s - used;
    if (left <= 0.0) break;
    // Size the next pass to about a quarter of the remaining time, so the budget is met
    // closely without many tiny passes.
    const double seconds_per_spp = used / done;
    pass_spp = int(std::clamp(left / seconds_per_spp / 4.0, 1.0, 1e6));
    if (left < seconds_per_spp) break;
  }
  if (settings.snapshots && !is_checkpoint(uint64_t(done))) take_snapshot(done);
  progress.finish();

  result.seconds = elapsed() - snapshot_seconds;
  result.samples_per_pixel = done;
  result.samples = pixels * uint64_t(done);
  result.image = average(done);
  return result;
}

}  // namespace emlt
