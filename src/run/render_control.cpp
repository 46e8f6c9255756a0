#include "emlt/run/render_control.h"

#include "emlt/core/interruption.h"
#include "emlt/run/checkpoint_file.h"

namespace emlt {

RenderControl::RenderControl(std::string checkpoint_path, double interval_seconds, Header header)
    : path_(std::move(checkpoint_path)),
      interval_(interval_seconds),
      header_(std::move(header)),
      last_write_(std::chrono::steady_clock::now()) {
  if (!path_.empty() && interval_ > 0.0) timer_ = std::thread([this] { run_timer(); });
}

RenderControl::~RenderControl() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  if (timer_.joinable()) timer_.join();
}

// Asks for a checkpoint `interval_` seconds after the last one was written; the workers see
// the request at their next poll and the integrator writes it from pause().
void RenderControl::run_timer() {
  std::unique_lock lock(mutex_);
  while (!quit_) {
    const auto last = last_write_;
    const auto due = last + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                std::chrono::duration<double>(interval_));
    // Woken early when a checkpoint was written meanwhile (on a signal): the next one is
    // then due an interval after it.
    if (wake_.wait_until(lock, due, [&] { return quit_ || last_write_ != last; })) continue;
    if (!interruption::checkpoint_due()) interruption::request_checkpoint();
    // Wait for that checkpoint to be written (pause() moves last_write_ on).
    wake_.wait(lock, [&] { return quit_ || !interruption::checkpoint_due(); });
  }
}

void RenderControl::write(const SaveState& save) {
  StateWriter state;
  save(state);
  checkpoint_file::write(path_, header_ ? header_() : std::string(), state.data());
  ++written_;
}

bool RenderControl::pause(const SaveState& save) {
  if (!path_.empty() && (interruption::checkpoint_due() || interruption::stop_requested()))
    write(save);
  {
    std::lock_guard lock(mutex_);
    last_write_ = std::chrono::steady_clock::now();
    interruption::clear_checkpoint();
  }
  wake_.notify_all();
  return interruption::stop_requested();
}

void RenderControl::finish(const SaveState& save) {
  if (!path_.empty()) write(save);
}

bool RenderControl::pause(RenderControl* control, const SaveState& save) {
  if (control) return control->pause(save);
  interruption::clear_checkpoint();
  return interruption::stop_requested();
}

void RenderControl::finish(RenderControl* control, const SaveState& save) {
  if (control) control->finish(save);
}

}  // namespace emlt
