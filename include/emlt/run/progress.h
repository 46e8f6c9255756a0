#pragma once
// Progress bar with ETA on stderr, drawn only when stderr is a terminal. Thread-safe:
// workers call advance(); at most one of them redraws, at most every 200 ms.
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace emlt {

class ProgressReporter {
 public:
  // enabled = false (or stderr not a terminal): nothing is ever printed.
  explicit ProgressReporter(bool enabled);
  ~ProgressReporter();

  // total units of work; time_limit_s > 0 makes the bar track time instead.
  void start(const std::string& label, uint64_t total, double time_limit_s = 0.0);
  void advance(uint64_t units);
  void finish();
  double elapsed_seconds() const;

  // Where the render stands, for a watcher on another thread (the Python module's progress
  // callback, which runs on the interpreter's thread while the render runs on its own).
  struct Status {
    std::string label;
    uint64_t done = 0, total = 0;
    double time_limit_s = 0.0, elapsed_s = 0.0;
  };
  Status status() const;

 private:
  void draw(bool final_line);

  bool enabled_;
  std::string label_;
  uint64_t total_ = 0;
  double time_limit_s_ = 0.0;
  std::atomic<uint64_t> done_{0};
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::mutex draw_mutex_;
  mutable std::mutex start_mutex_;  // label_, total_, time_limit_s_, start_ against status()
  bool drawn_ = false;
};

}  // namespace emlt
