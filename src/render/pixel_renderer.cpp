#include "emlt/render/pixel_renderer.h"

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/render/interruption.h"
#include "emlt/render/render_control.h"
#include "emlt/render/snapshot.h"

namespace emlt {

namespace {

// 8 x 8 pixels: a pass of a 256 x 256 image is 1,024 tasks, so that on 16 cores the last
// tiles of a pass leave the others idle only briefly (16 x 16 tiles ran pt 1-6 % slower at
// 16 threads; docs/performance.md, "To 16 threads"). A tile's samples do not depend on it.
constexpr int kTileSize = 8;

// Samples from each pixel's count up to `last`, added to its sum in sample order. Returns
// early (every pixel's count saying how far it got) when an interruption is requested.
uint64_t render_pass(const Scene& scene, const RenderSettings& settings,
                     ProgressReporter& progress, const RadianceEstimator& radiance, int first,
                     int last, PixelRenderState& state) {
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  tbb::combinable<uint64_t> invalid([] { return uint64_t(0); });
  tbb::parallel_for(
      tbb::blocked_range2d<int>(0, height, kTileSize, 0, width, kTileSize),
      [&](const tbb::blocked_range2d<int>& tile) {
        uint64_t& tile_invalid = invalid.local();
        uint64_t tile_samples = 0;
        for (int y = tile.rows().begin(); y < tile.rows().end(); ++y) {
          if (!owns_row(y)) continue;
          for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) {
            const uint64_t pixel = uint64_t(y) * uint64_t(width) + uint64_t(x);
            int k = std::max(first, int(state.counts[pixel]));
            if (k >= last || interruption::requested()) continue;
            const uint64_t pixel_stream = derive_stream_seed(settings.seed, pixel);
            DVec3 sum = state.sums[pixel];
            const int begin = k;
            for (; k < last && !interruption::requested(); ++k) {
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
            state.sums[pixel] = sum;
            state.counts[pixel] = k;
            tile_samples += uint64_t(k - begin);
            interruption::poll(uint64_t(k - begin));
          }
        }
        progress.advance(tile_samples);
      });
  return invalid.combine(std::plus<uint64_t>());
}

}  // namespace

void PixelRenderState::save(StateWriter& out) const {
  out.put_vector(sums);
  out.put_vector(counts);
  out.put(schedule);
  out.put(invalid);
}

void PixelRenderState::load(StateReader& in, int width, int height) {
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  sums = in.get_vector<DVec3>(pixels);
  counts = in.get_vector<int32_t>(pixels);
  schedule = in.get<PassSchedule::Saved>();
  invalid = in.get<uint64_t>();
  for (uint64_t i = 0; i < pixels; ++i) {
    const int32_t c = counts[i];
    const bool valid = owns_row(int(i / uint64_t(width)))
                           ? c >= schedule.done && c <= std::max(schedule.done, schedule.pass_end)
                           : c == 0;
    if (!valid) throw StateError("a pixel's sample count lies outside the pass under way");
  }
  resumed = true;
}

PixelRenderState::Totals PixelRenderState::totals() const {
  Totals t;
  t.sums.resize(3 * sums.size());
  for (size_t i = 0; i < sums.size(); ++i)
    for (int c = 0; c < 3; ++c) t.sums[3 * i + size_t(c)] = sums[i][c];
  t.counts = counts;
  // Each pixel is some one rank's: the others add +0.0 and 0, which changes no bit.
  cluster::sum_to_root(t.sums);
  cluster::sum_to_root(t.counts);
  return t;
}

Image PixelRenderState::Totals::image(int width, int height) const {
  Image image(width, height);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] =
        counts[i] > 0
            ? Rgb(DVec3(sums[3 * i], sums[3 * i + 1], sums[3 * i + 2]) / double(counts[i]))
            : Rgb(0.0f);
  return image;
}

bool PixelRenderState::behind(int samples, int width) const {
  const size_t rows = width > 0 ? counts.size() / size_t(width) : 0;
  for (size_t y = 0; y < rows; ++y) {
    if (!owns_row(int(y))) continue;
    const int32_t* row = &counts[y * size_t(width)];
    if (std::any_of(row, row + width, [&](int32_t c) { return c < samples; })) return true;
  }
  return false;
}

// Bands of 16 rows, not tied to the tile size (a tile skips the rows of other ranks' bands):
// BDPT assigns its 16 x 16 tiles by their first row.
constexpr int kRankBandRows = 16;

bool owns_row(int y) {
  return (y / kRankBandRows) % cluster::size() == cluster::rank();
}

RenderResult render_pixels(const Scene& scene, const RenderSettings& settings,
                           ProgressReporter& progress, const RadianceEstimator& radiance,
                           PixelRenderState& state, const std::function<void()>& on_pause) {
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  if (!state.resumed) {
    state.sums.assign(pixels, DVec3(0.0));
    state.counts.assign(pixels, 0);
    state.invalid = 0;
  }
  // Between passes every pixel has `samples` samples.
  const auto average = [&](int samples) {
    const PixelRenderState::Totals totals = state.totals();
    Image image(width, height);
    const double scale = samples > 0 ? 1.0 / samples : 0.0;
    for (uint64_t i = 0; i < pixels; ++i)
      image.pixels[i] = Rgb(DVec3(totals.sums[3 * i], totals.sums[3 * i + 1], totals.sums[3 * i + 2]) * scale);
    return image;
  };

  const int threads = settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  PassSchedule schedule(settings, std::numeric_limits<int>::max());
  if (state.resumed) schedule.restore(state.schedule);
  const bool timed = settings.time_limit_s > 0.0;
  progress.start("rendering", timed ? 0 : pixels * uint64_t(schedule.max_samples()), settings.time_limit_s);
  progress.advance(pixels * uint64_t(schedule.samples()));

  RenderResult result;
  bool mid_pass = state.resumed && state.schedule.pass_end > 0;
  while (schedule.more()) {
    const int first = schedule.pass_begin(), last = schedule.pass_end();
    arena.execute([&] {
      state.invalid += render_pass(scene, settings, progress, radiance, first, last, state);
    });
    const bool incomplete = state.behind(last, width);
    // Every rank takes the same decision here (interruption.h).
    const interruption::Decision decision = interruption::agree(incomplete);
    mid_pass = decision.incomplete;
    if (!mid_pass) schedule.complete_pass(average);
    if (decision.pause()) {
      state.schedule = schedule.save(mid_pass);
      on_pause();
      if (decision.stop && (mid_pass || schedule.more())) {
        result.interrupted = true;
        break;
      }
    }
  }
  if (!result.interrupted) schedule.finish(average);
  progress.finish();
  state.schedule = schedule.save(mid_pass);

  const PixelRenderState::Totals totals = state.totals();
  std::vector<uint64_t> invalid = {state.invalid};
  cluster::sum_to_root(invalid);
  uint64_t total = 0;
  for (const int32_t c : totals.counts) total += uint64_t(c);
  result.seconds = schedule.seconds();
  result.samples_per_pixel = schedule.samples();
  result.samples = total;
  result.per_pixel = pixels > 0 ? double(total) / double(pixels) : 0.0;
  result.invalid_samples = invalid[0];
  result.image = totals.image(width, height);
  // A stopped render's log ends with the image it writes.
  if (result.interrupted && settings.snapshots)
    settings.snapshots->snapshot(result.per_pixel, result.seconds, result.image, {});
  return result;
}

RenderResult render_pixels(const Scene& scene, const RenderSettings& settings,
                           ProgressReporter& progress, const RadianceEstimator& radiance) {
  PixelRenderState state;
  RenderControl* control = settings.control;
  if (control && !control->resume_state().empty()) {
    StateReader in(control->resume_state());
    state.load(in, scene.camera().width(), scene.camera().height());
    in.expect_end();
  }
  const auto save = [&](StateWriter& out) { state.save(out); };
  RenderResult result = render_pixels(scene, settings, progress, radiance, state,
                                      [&] { RenderControl::pause(control, save); });
  if (!result.interrupted) RenderControl::finish(control, save);
  return result;
}

}  // namespace emlt
