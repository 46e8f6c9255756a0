#pragma once
// How a per-pixel sample budget is split into passes, for integrators that render whole
// passes over the image (direct, pt, bdpt). Passes end at power-of-two sample counts
// (checkpoints: snapshot.h) whether or not a convergence log listens, are at most
// `max_pass` samples long, and under a time budget are sized to about a quarter of the
// remaining time so the budget is met closely without many tiny passes. The schedule also
// keeps the clock, without the time spent taking snapshots.
#include <chrono>
#include <functional>

#include "emlt/render/image.h"
#include "emlt/render/settings.h"

namespace emlt {

class PassSchedule {
 public:
  // The image after a given number of samples per pixel (for snapshots).
  using ImageAt = std::function<Image(int samples)>;

  PassSchedule(const RenderSettings& settings, int max_pass);

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
  bool stopped_ = false;
  std::chrono::steady_clock::time_point start_;
  double snapshot_seconds_ = 0.0;
};

}  // namespace emlt
