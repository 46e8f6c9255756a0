#include "emlt/run/pass_runner.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <limits>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/run/render_control.h"
#include "emlt/run/snapshot.h"

namespace emlt {

namespace {

// Tiles are the tasks of a pass and, for a step that splats, the blocks whose splat lists
// are added in order. 8 x 8 pixels: a pass of a 256 x 256 image is 1,024 tasks, so that on
// 16 cores the last tiles of a pass leave the others idle only briefly (16 x 16 tiles ran
// pt 1-6 % slower at 16 threads; docs/performance.md, "To 16 threads"). A splatting step
// keeps 16 x 16, fewer lists to keep and merge; its images depend on this size. Both divide
// the rank bands (pixel_state.cpp), so a tile is one rank's.
constexpr int kPixelTileSize = 8;
constexpr int kSplatTileSize = 16;
// A splatting step's samples per pass are bounded so the splat lists of one pass stay small
// (a few splats of 20 bytes per sample); the bound depends on the image only, so passes
// never depend on the thread count.
constexpr uint64_t kSplatSamplesPerPass = uint64_t(1) << 18;

}  // namespace

PassRunner::PassRunner(const Scene& scene, const RenderSettings& settings,
                       ProgressReporter& progress, PixelSampleStep& step, PixelRenderState& state)
    : scene_(scene),
      settings_(settings),
      progress_(progress),
      step_(step),
      state_(state),
      width_(scene.camera().width()),
      height_(scene.camera().height()),
      pixels_(uint64_t(width_) * uint64_t(height_)),
      film_(step.splats() ? width_ : 0, step.splats() ? height_ : 0, step.film_layers()) {
  const int size = step.splats() ? kSplatTileSize : kPixelTileSize;
  for (int y = 0; y < height_; y += size)
    for (int x = 0; x < width_; x += size)
      tiles_.push_back({x, y, std::min(x + size, width_), std::min(y + size, height_)});
  outputs_.resize(tiles_.size());
}

PassRunner::PassRunner(const Scene& scene, const RenderSettings& settings,
                       ProgressReporter& progress, PixelSampleStep& step)
    : PassRunner(scene, settings, progress, step, std::make_unique<PixelRenderState>()) {}

PassRunner::PassRunner(const Scene& scene, const RenderSettings& settings,
                       ProgressReporter& progress, PixelSampleStep& step,
                       std::unique_ptr<PixelRenderState> state)
    : PassRunner(scene, settings, progress, step, *state) {
  own_state_ = std::move(state);
}

PassRunner::~PassRunner() = default;

void PassRunner::save(StateWriter& out) const {
  state_.save(out);
  step_.save(out);
  if (!step_.splats()) return;
  film_.save(out);
  for (const TileOutput& tile : outputs_) {
    out.put_vector(tile.splats.records);
    out.put(tile.invalid.count);
  }
}

void PassRunner::load(StateReader& in) {
  state_.load(in, width_, height_);
  step_.load(in);
  if (!step_.splats()) return;
  film_.load(in);
  for (TileOutput& tile : outputs_) {
    // A tile makes a few splats per sample; kSplatSamplesPerPass bounds a pass's samples.
    tile.splats.records = in.get_vector_up_to<SplatRecord>(64 * kSplatSamplesPerPass);
    for (const SplatRecord& r : tile.splats.records)
      if (r.pixel >= pixels_ || r.layer >= step_.film_layers())
        throw StateError("a saved splat lies outside the image");
    // Dropped values are counted in the pixels' state once a pass's workers return, so
    // these are 0 in a checkpoint written since; the field keeps older ones readable.
    tile.invalid.count = in.get<uint64_t>();
  }
}

// Samples from each pixel's count up to `last`, added to its sum in sample order. Returns
// early (every pixel's count saying how far it got) when an interruption is requested.
void PassRunner::render_pass(int first, int last) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles_.size(), 1),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t index = range.begin(); index < range.end(); ++index)
                        if (owns_row(tiles_[index].y0)) render_tile(index, first, last);
                    });
  // The values dropped count as soon as the workers return, so a checkpoint in mid-pass
  // keeps them.
  for (TileOutput& out : outputs_) {
    state_.invalid += out.invalid.count;
    out.invalid.count = 0;
  }
}

void PassRunner::render_tile(size_t index, int first, int last) {
  const Tile& tile = tiles_[index];
  TileOutput& out = outputs_[index];
  uint64_t tile_samples = 0;
  for (int y = tile.y0; y < tile.y1; ++y) {
    for (int x = tile.x0; x < tile.x1; ++x) {
      const uint64_t pixel = uint64_t(y) * uint64_t(width_) + uint64_t(x);
      int k = std::max(first, int(state_.counts[pixel]));
      if (k >= last || interruption::requested()) continue;
      const uint64_t pixel_stream = derive_stream_seed(settings_.seed, pixel);
      DVec3& sum = state_.sums[pixel];
      const int begin = k;
      for (; k < last && !interruption::requested(); ++k) {
        Rng rng(pixel_stream, uint64_t(k));
        step_.sample(x, y, rng, sum, out);
      }
      state_.counts[pixel] = k;
      tile_samples += uint64_t(k - begin);
      interruption::poll(uint64_t(k - begin));
    }
  }
  progress_.advance(tile_samples);
}

// Adds the pass's splats to the film in tile order (every rank's, on rank 0), the same bits
// at any thread and rank count.
void PassRunner::merge_pass_splats() {
  std::vector<SplatList> lists(outputs_.size());
  if (cluster::size() == 1) {
    for (size_t i = 0; i < outputs_.size(); ++i) lists[i].records.swap(outputs_[i].splats.records);
  } else {
    StateWriter mine;
    for (size_t i = 0; i < outputs_.size(); ++i) {
      if (!owns_row(tiles_[i].y0)) continue;
      mine.put<uint64_t>(i);
      mine.put_vector(outputs_[i].splats.records);
      outputs_[i].splats.records.clear();
    }
    for (const std::string_view part : cluster::gather_to_root(mine.data())) {
      StateReader in(part);
      while (in.remaining() > 0) {
        const uint64_t i = in.get<uint64_t>();
        lists.at(i).records = in.get_vector_up_to<SplatRecord>(UINT64_MAX / sizeof(SplatRecord));
      }
    }
  }
  film_.add_in_order(lists);
}

// The image so far, complete on rank 0. The pixels' sums average over their own samples;
// a splat carries W_e of the whole film, so the film is scaled by pixels / light paths,
// one light path per pixel sample.
Image PassRunner::image_now() {
  const PixelRenderState::Totals totals = state_.totals();
  samples_ = totals.samples();
  if (!step_.splats()) {
    Image image = totals.image(width_, height_);
    step_.add_own_film(image, samples_);
    return image;
  }
  const uint64_t light_paths = samples_;
  splat_scale_ = light_paths > 0 ? double(pixels_) / double(light_paths) : 0.0;
  Image image(width_, height_);
  for (uint64_t i = 0; i < pixels_; ++i) {
    const double camera_scale = totals.counts[i] > 0 ? 1.0 / totals.counts[i] : 0.0;
    const DVec3 sum(totals.sums[3 * i], totals.sums[3 * i + 1], totals.sums[3 * i + 2]);
    image.pixels[i] = Rgb(sum * camera_scale + film_.sums()[i] * splat_scale_);
  }
  return image;
}

RenderResult PassRunner::run(const std::function<void()>& on_pause) {
  if (!state_.resumed) {
    state_.sums.assign(pixels_, DVec3(0.0));
    state_.counts.assign(pixels_, 0);
    state_.invalid = 0;
  }
  // Between passes every pixel has `samples` samples.
  const PassSchedule::ImageAt image_at = [&](int samples) {
    if (step_.splats()) return image_now();
    const PixelRenderState::Totals totals = state_.totals();
    Image image(width_, height_);
    const double scale = samples > 0 ? 1.0 / samples : 0.0;
    for (uint64_t i = 0; i < pixels_; ++i)
      image.pixels[i] =
          Rgb(DVec3(totals.sums[3 * i], totals.sums[3 * i + 1], totals.sums[3 * i + 2]) * scale);
    step_.add_own_film(image, uint64_t(samples) * pixels_);
    return image;
  };

  const int threads =
      settings_.threads > 0 ? settings_.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  const int max_pass =
      step_.splats()
          ? int(std::max<uint64_t>(1, kSplatSamplesPerPass / std::max<uint64_t>(pixels_, 1)))
          : std::numeric_limits<int>::max();
  PassSchedule schedule(settings_, max_pass);
  if (state_.resumed) schedule.restore(state_.schedule);
  const bool timed = settings_.time_limit_s > 0.0;
  progress_.start("rendering", timed ? 0 : pixels_ * uint64_t(schedule.max_samples()),
                  settings_.time_limit_s);
  progress_.advance(pixels_ * uint64_t(schedule.samples()));

  RenderResult result;
  bool mid_pass = state_.resumed && state_.schedule.pass_end > 0;
  while (schedule.more()) {
    const int first = schedule.pass_begin(), last = schedule.pass_end();
    arena.execute([&] { render_pass(first, last); });
    const bool incomplete = state_.behind(last, width_);
    // Every rank takes the same decision here (interruption.h).
    const interruption::Decision decision = interruption::agree(incomplete);
    mid_pass = decision.incomplete;
    if (!mid_pass) {
      merge_pass_splats();
      schedule.complete_pass(image_at);
    }
    if (decision.pause()) {
      state_.schedule = schedule.save(mid_pass);
      on_pause();
      if (decision.stop && (mid_pass || schedule.more())) {
        result.interrupted = true;
        break;
      }
    }
  }
  if (!result.interrupted)
    schedule.finish(image_at);
  else if (step_.splats())
    merge_pass_splats();  // the image of a stop inside a pass includes its splats so far
  progress_.finish();
  state_.schedule = schedule.save(mid_pass);

  result.image = image_now();
  const uint64_t samples = samples_;
  std::vector<uint64_t> invalid = {state_.invalid};
  cluster::sum_to_root(invalid);
  result.seconds = schedule.seconds();
  result.samples_per_pixel = schedule.samples();
  result.samples = samples;
  result.per_pixel = pixels_ > 0 ? double(samples) / double(pixels_) : 0.0;
  result.invalid_samples = invalid[0];
  // A stopped render's log ends with the image it writes.
  if (result.interrupted && settings_.snapshots)
    settings_.snapshots->snapshot(result.per_pixel, result.seconds, result.image, {});
  return result;
}

RenderResult PassRunner::render() {
  RenderControl* control = settings_.control;
  if (control && !control->resume_state().empty()) {
    StateReader in(control->resume_state());
    load(in);
    in.expect_end();
  }
  const auto save = [&](StateWriter& out) { this->save(out); };
  RenderResult result = run([&] { RenderControl::pause(control, save); });
  if (!result.interrupted) RenderControl::finish(control, save);
  return result;
}

}  // namespace emlt
