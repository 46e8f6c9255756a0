#include "emlt/run/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace emlt {

ProgressReporter::ProgressReporter(bool enabled) : enabled_(enabled && isatty(STDERR_FILENO)) {
  start_ = last_draw_ = std::chrono::steady_clock::now();
}

ProgressReporter::~ProgressReporter() {
  finish();
}

void ProgressReporter::start(const std::string& label, uint64_t total, double time_limit_s) {
  std::lock_guard lock(start_mutex_);
  label_ = label;
  total_ = total;
  time_limit_s_ = time_limit_s;
  done_ = 0;
  start_ = std::chrono::steady_clock::now();
  drawn_ = false;
}

double ProgressReporter::elapsed_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

ProgressReporter::Status ProgressReporter::status() const {
  std::lock_guard lock(start_mutex_);
  return {label_, done_.load(std::memory_order_relaxed), total_, time_limit_s_, elapsed_seconds()};
}

void ProgressReporter::advance(uint64_t units) {
  done_.fetch_add(units, std::memory_order_relaxed);
  if (!enabled_) return;
  std::unique_lock lock(draw_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(200)) return;
  last_draw_ = now;
  draw(false);
}

void ProgressReporter::draw(bool final_line) {
  const double elapsed = elapsed_seconds();
  double fraction = total_ ? double(done_.load()) / double(total_) : 0.0;
  if (time_limit_s_ > 0.0) fraction = std::max(fraction, elapsed / time_limit_s_);
  if (fraction > 1.0) fraction = 1.0;
  const int width = 30, filled = int(fraction * width);
  std::string bar(size_t(filled), '=');
  if (filled < width) bar += '>' + std::string(size_t(width - filled - 1), ' ');
  const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  std::fprintf(stderr, "\r%s [%s] %5.1f%%  %6.1fs  ETA %6.1fs%s", label_.c_str(), bar.c_str(),
               100.0 * fraction, elapsed, eta, final_line ? "\n" : "");
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressReporter::finish() {
  if (!enabled_ || !drawn_) return;
  std::lock_guard lock(draw_mutex_);
  draw(true);
  drawn_ = false;
}

}  // namespace emlt
