#include "emlt/render/pixel_renderer.h"

#include "emlt/render/pass_schedule.h"

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>

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
              const Ray ray = camera.generate_ray(camera.filter().sample(x, y, jitter), u_lens);
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
  std::vector<DVec3> sums(pixels, DVec3(0.0));
  const auto average = [&](int samples) {
    Image image(width, height);
    const double scale = samples > 0 ? 1.0 / samples : 0.0;
    for (uint64_t i = 0; i < pixels; ++i) image.pixels[i] = Rgb(sums[i] * scale);
    return image;
  };

  const int threads = settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  PassSchedule schedule(settings, std::numeric_limits<int>::max());
  const bool timed = settings.time_limit_s > 0.0;
  progress.start("rendering", timed ? 0 : pixels * uint64_t(schedule.max_samples()), settings.time_limit_s);

  RenderResult result;
  while (schedule.more()) {
    const int first = schedule.pass_begin(), last = schedule.pass_end();
    arena.execute([&] {
      result.invalid_samples += render_pass(scene, settings, progress, radiance, first, last, sums);
    });
    schedule.complete_pass(average);
  }
  schedule.finish(average);
  progress.finish();

  result.seconds = schedule.seconds();
  result.samples_per_pixel = schedule.samples();
  result.samples = pixels * uint64_t(schedule.samples());
  result.image = average(schedule.samples());
  return result;
}

}  // namespace emlt
