#pragma once
// The one loop of every integrator that renders the image sample by pixel sample in whole
// passes (direct, pt, bdpt, ptracer). The integrator supplies a step, what one pixel sample
// does, and the state of its own; the runner owns everything else:
// - the budget: `--spp` passes, or `--time` whole passes until the time is spent (spp then
//   caps it), ending at power-of-two samples for the convergence log (pass_schedule.h);
// - the order: sample k of pixel i draws from the stream (seed, i, k), each pixel is summed
//   by one task in sample order, and splats are added to the film tile by tile in tile
//   order, so the image is the same bits at any thread count, in one pass or many, in one
//   run or resumed from a checkpoint;
// - the rank share (pixel_state.h) and the exact reduction of the ranks' pixels and splats
//   on rank 0, so `mpirun -n R` gives the one-process image;
// - stops and checkpoints: workers return at a stop signal or a checkpoint falling due,
//   every rank agrees on what to do (interruption.h), and the state is saved
//   (render_control.h) or the render ends with the image normalised for the work done;
// - progress, the convergence log's snapshots and the result's statistics.
#include <functional>
#include <memory>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/core/state_io.h"
#include "emlt/film/splat_film.h"
#include "emlt/path/vertex.h"
#include "emlt/run/integrator.h"
#include "emlt/run/pixel_state.h"

namespace emlt {

// What one tile's samples leave during a pass besides their pixels' sums: light-tracing
// splats, added to the film in tile order when the pass completes, and the values dropped.
struct TileOutput {
  SplatList splats;
  InvalidCounter invalid;
};

// One pixel sample of an integrator, and the state it keeps beyond the pixels' sums.
class PixelSampleStep {
 public:
  virtual ~PixelSampleStep() = default;

  // One sample of pixel (x, y). `rng` is the sample's own stream (seed, pixel, sample
  // number), unused so far; the step adds its estimate of the pixel's value to `pixel_sum`
  // (several additions are fine: their order is part of the image's bits), splats
  // contributions to other pixels to out.splats, as values of the whole film (the camera's
  // W_e, camera.h), and counts the values it drops (not finite, negative) in out.invalid.
  // Called concurrently for distinct pixels, each pixel's samples in order by one thread.
  virtual void sample(int x, int y, Rng& rng, DVec3& pixel_sum, TileOutput& out) = 0;

  // Whether sample() splats: the runner then keeps a film, bounds the passes so that a
  // pass's splat lists stay small, and scales the film by pixels / samples (one light path
  // per pixel sample) into the image.
  virtual bool splats() const { return false; }
  // Layers of the film besides the image (SplatFilm), which SplatRecord::layer names.
  virtual int film_layers() const { return 0; }

  // A step that deposits into a film of its own (ERPT's chains, which land anywhere): adds
  // that film, as image values after `samples` pixel samples of every pixel together, to
  // `image` (complete on rank 0). A collective call, made at every image the runner takes.
  virtual void add_own_film(Image& image, uint64_t samples) {
    (void)image;
    (void)samples;
  }

  // The step's own state, checkpointed after the pixels' (e.g. per-pixel sums of its own).
  // load() throws StateError for a state that does not fit.
  virtual void save(StateWriter&) const {}
  virtual void load(StateReader&) {}
};

class PassRunner {
 public:
  // The runner keeps references to all of them.
  PassRunner(const Scene& scene, const RenderSettings& settings, ProgressReporter& progress,
             PixelSampleStep& step);
  // A render inside another, whose state holds the pixels' sums, counts and schedule:
  // continued when state.resumed, else started afresh.
  PassRunner(const Scene& scene, const RenderSettings& settings, ProgressReporter& progress,
             PixelSampleStep& step, PixelRenderState& state);
  ~PassRunner();

  // The whole render through settings.control: resumes from its state, writes a checkpoint
  // at every pause and a last one when the budget is done.
  RenderResult render();

  // The whole state a checkpoint holds: the pixels, the step's, the film and the splats of
  // a pass under way. load() throws StateError for a state that does not fit.
  void save(StateWriter& out) const;
  void load(StateReader& in);

  // Renders passes until the budget is spent or every rank agrees to stop. At each pause
  // agreed by every rank (a checkpoint due, a stop) calls `on_pause` with the state
  // consistent, ready to save. Leaves the final state in place; the result's image is
  // complete on rank 0 only.
  RenderResult run(const std::function<void()>& on_pause);

  // After a render: the pixels (this rank's), the film of the splats (rank 0), and the
  // scale that makes the film's sums image values.
  const PixelRenderState& state() const { return state_; }
  const SplatFilm& film() const { return film_; }
  double splat_scale() const { return splat_scale_; }

 private:
  PassRunner(const Scene& scene, const RenderSettings& settings, ProgressReporter& progress,
             PixelSampleStep& step, std::unique_ptr<PixelRenderState> state);
  void render_pass(int first, int last);
  void render_tile(size_t index, int first, int last);
  void merge_pass_splats();
  Image image_now();

  const Scene& scene_;
  const RenderSettings& settings_;
  ProgressReporter& progress_;
  PixelSampleStep& step_;
  std::unique_ptr<PixelRenderState> own_state_;  // when the render is not inside another
  PixelRenderState& state_;
  int width_, height_;
  uint64_t pixels_;
  struct Tile {
    int x0, y0, x1, y1;
  };
  std::vector<Tile> tiles_;
  std::vector<TileOutput> outputs_;  // the pass under way's, one per tile
  SplatFilm film_;
  double splat_scale_ = 0.0;
  uint64_t samples_ = 0;  // of every pixel together, as of the last image_now()
};

}  // namespace emlt
