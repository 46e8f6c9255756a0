#include "emlt/render/pass_schedule.h"

#include <algorithm>
#include <limits>

#include "emlt/render/snapshot.h"

namespace emlt {

namespace {
double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

PassSchedule::PassSchedule(const RenderSettings& settings, int max_pass)
    : settings_(settings),
      timed_(settings.time_limit_s > 0.0),
      max_pass_(std::max(max_pass, 1)),
      // A time budget with no explicit sample cap runs until the time is up.
      max_samples_(timed_ && settings.spp <= 0 ? std::numeric_limits<int>::max()
                                               : std::max(settings.spp, 1)),
      pass_samples_(timed_ ? 1 : max_pass_),
      start_(std::chrono::steady_clock::now()) {}

int PassSchedule::pass_end() const {
  const uint64_t wanted = uint64_t(done_) + uint64_t(std::min(pass_samples_, max_samples_ - done_));
  return int(std::min(wanted, next_checkpoint(uint64_t(done_))));
}

double PassSchedule::seconds() const { return since(start_) - snapshot_seconds_; }

void PassSchedule::snapshot(const ImageAt& image_at) {
  const auto begin = std::chrono::steady_clock::now();
  settings_.snapshots->snapshot(done_, seconds(), image_at(done_), {});
  snapshot_seconds_ += since(begin);
}

void PassSchedule::complete_pass(const ImageAt& image_at) {
  done_ = pass_end();
  if (settings_.snapshots && is_checkpoint(uint64_t(done_))) snapshot(image_at);
  if (!timed_) return;
  const double used = seconds(), left = settings_.time_limit_s - used;
  const double seconds_per_sample = used / done_;
  if (left <= 0.0 || left < seconds_per_sample) {
    stopped_ = true;
    return;
  }
  pass_samples_ = int(std::clamp(left / seconds_per_sample / 4.0, 1.0, double(max_pass_)));
}

void PassSchedule::finish(const ImageAt& image_at) {
  if (settings_.snapshots && !is_checkpoint(uint64_t(done_))) snapshot(image_at);
}

}  // namespace emlt
