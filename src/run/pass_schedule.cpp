#include "emlt/run/pass_schedule.h"

#include <algorithm>
#include <limits>

#include "emlt/core/cluster.h"
#include "emlt/core/state_io.h"
#include "emlt/run/snapshot.h"

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
  if (resumed_pass_end_ > 0) return resumed_pass_end_;
  const uint64_t wanted = uint64_t(done_) + uint64_t(std::min(pass_samples_, max_samples_ - done_));
  return int(std::min(wanted, next_checkpoint(uint64_t(done_))));
}

double PassSchedule::seconds() const {
  return earlier_seconds_ + since(start_) - snapshot_seconds_;
}

PassSchedule::Saved PassSchedule::save(bool mid_pass) const {
  return {done_, mid_pass ? pass_end() : 0, pass_samples_, seconds()};
}

void PassSchedule::restore(const Saved& saved) {
  if (saved.done < 0 || saved.pass_end < 0 || saved.pass_samples < 1 ||
      (saved.pass_end > 0 && saved.pass_end <= saved.done) || !(saved.seconds >= 0.0))
    throw StateError("the saved pass schedule is inconsistent");
  if (saved.done > max_samples_ || saved.pass_end > max_samples_)
    throw StateError("the checkpoint has " + std::to_string(std::max(saved.done, saved.pass_end)) +
                     " samples per pixel done or under way, more than this run's budget of " +
                     std::to_string(max_samples_) +
                     " (a resumed render may extend the budget, not cut it)");
  done_ = saved.done;
  resumed_pass_end_ = saved.pass_end;
  pass_samples_ = std::min(saved.pass_samples, max_pass_);
  earlier_seconds_ = saved.seconds;
  start_ = std::chrono::steady_clock::now();
  snapshot_seconds_ = 0.0;
  // A time budget already spent (the same --time given again) renders nothing more.
  stopped_ = timed_ && resumed_pass_end_ == 0 && seconds() >= settings_.time_limit_s;
  if (cluster::size() > 1) {
    std::string decision(1, char(stopped_));
    cluster::broadcast(decision);
    stopped_ = decision[0] != 0;
  }
}

void PassSchedule::snapshot(const ImageAt& image_at) {
  const auto begin = std::chrono::steady_clock::now();
  settings_.snapshots->snapshot(done_, seconds(), image_at(done_), {});
  snapshot_seconds_ += since(begin);
}

void PassSchedule::complete_pass(const ImageAt& image_at) {
  done_ = pass_end();
  resumed_pass_end_ = 0;
  if (settings_.snapshots && is_checkpoint(uint64_t(done_))) snapshot(image_at);
  if (!timed_) return;
  const double used = seconds(), left = settings_.time_limit_s - used;
  const double seconds_per_sample = used / done_;
  if (left <= 0.0 || left < seconds_per_sample)
    stopped_ = true;
  else
    pass_samples_ = int(std::clamp(left / seconds_per_sample / 4.0, 1.0, double(max_pass_)));
  // Under MPI rank 0's clock decides for every rank, so that they run the same passes.
  if (cluster::size() > 1) {
    StateWriter out;
    out.put<int32_t>(pass_samples_);
    out.put<uint8_t>(stopped_);
    std::string decision = out.take();
    cluster::broadcast(decision);
    StateReader in(decision);
    pass_samples_ = in.get<int32_t>();
    stopped_ = in.get<uint8_t>() != 0;
  }
}

void PassSchedule::finish(const ImageAt& image_at) {
  if (settings_.snapshots && !is_checkpoint(uint64_t(done_))) snapshot(image_at);
}

}  // namespace emlt
