#pragma once
// How a per-pixel sample budget is split into passes, for integrators that render whole
// passes over the image (direct, pt, bdpt). Passes end at power-of-two sample counts
// (checkpoints: snapshot.h) whether or not a convergence log listens, are at most
// `max_pass` samples long, and under a time budget are sized to about a quarter of the
// remaining time so the budget is met closely without many tiny passes. The schedule also
// keeps the clock, without the time spent taking snapshots.
#include <chrono>
#include <functional>

#include "emlt/image/image.h"
#include "emlt/settings/settings.h"

namespace emlt {

class PassSchedule {
 public:
  // The image after a given number of samples per pixel (for snapshots).
  using ImageAt = std::function<Image(int samples)>;

  PassSchedule(const RenderSettings& settings, int max_pass);

  // What a checkpoint keeps of the schedule. `pass_end` is the end of the pass that was
  // under way (0 when the pause fell between passes): a resumed render finishes that pass
  // first, as the uninterrupted one would have. `seconds`: rendering time so far.
  struct Saved {
    int32_t done = 0, pass_end = 0, pass_samples = 0;
    double seconds = 0.0;
  };
  Saved save(bool mid_pass) const;
  // Continues from a saved schedule (the budget may have grown since). Throws StateError
  // when the settings' budget is smaller than the work already done.
  void restore(const Saved& saved);

  int max_samples() const { return max_samples_; }
  bool more() const { return !stopped_ && done_ < max_samples_; }
  int pass_begin() const { return done_; }
  int pass_end() const;
  // After rendering samples [pass_begin, pass_end) of every pixel.
  void complete_pass(const ImageAt& image_at);
  // After the last pass: a final snapshot unless the last pass ended on a checkpoint.
  void finish(const ImageAt& image_at);

  int samples() const { return done_; }
  double seconds() const;

 private:
  void snapshot(const ImageAt& image_at);

  const RenderSettings& settings_;
  bool timed_;
  int max_pass_, max_samples_, pass_samples_;
  int done_ = 0;
  int resumed_pass_end_ = 0;  // a restored pass under way, until it completes
  bool stopped_ = false;
  std::chrono::steady_clock::time_point start_;
  double snapshot_seconds_ = 0.0;
  double earlier_seconds_ = 0.0;  // of the runs before a resume
};

}  // namespace emlt
