#pragma once
// What ties a running render to the world outside its settings (RenderSettings::control):
// checkpoints written every interval and when a stop signal arrives, and the state a
// resumed render starts from. Integrators poll interruption::requested() in their workers;
// when the workers have returned for it, with every path in hand finished, the integrator
// calls pause() with a function that writes its whole state, and ends the render (keeping
// what it has) when pause() says so. Because the state is complete (random-stream
// positions, exact fixed-point films, counters), continuing from it, in this process or in
// a later one, gives the same bits as a render never interrupted.
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "emlt/core/state_io.h"
#include "emlt/run/checkpoint_file.h"

namespace emlt {

class RenderControl {
 public:
  using SaveState = std::function<void(StateWriter&)>;
  using Header = std::function<std::string()>;

  // checkpoint_path empty: no checkpoints (a stop signal still ends the render with what it
  // has). `header` gives the command line's section of each checkpoint (checkpoint_file.h).
  RenderControl(std::string checkpoint_path, double interval_seconds, Header header);
  ~RenderControl();
  RenderControl(const RenderControl&) = delete;
  RenderControl& operator=(const RenderControl&) = delete;

  // The integrator's state to resume from (empty: a fresh render), with the checkpoint format
  // it was written in (checkpoint_file.h).
  void set_resume_state(std::string state, uint32_t format = checkpoint_file::kVersion) {
    resume_state_ = std::move(state);
    resume_format_ = format;
  }
  const std::string& resume_state() const { return resume_state_; }
  uint32_t resume_format() const { return resume_format_; }

  // At a pause: writes a checkpoint when one is configured (whether it fell due or a stop
  // signal came) and returns whether the render must stop now.
  bool pause(const SaveState& save);
  // When the budget is done: a last checkpoint, from which a later run may extend it.
  void finish(const SaveState& save);

  // Either of the above through a control that may be absent (library use, tests): without
  // one, nothing is saved and only a stop request ends the render.
  static bool pause(RenderControl* control, const SaveState& save);
  static void finish(RenderControl* control, const SaveState& save);

  int checkpoints_written() const { return written_; }
  const std::string& checkpoint_path() const { return path_; }

 private:
  void write(const SaveState& save);
  void run_timer();

  std::string path_;
  double interval_;
  Header header_;
  std::string resume_state_;
  uint32_t resume_format_ = checkpoint_file::kVersion;
  int written_ = 0;

  std::mutex mutex_;
  std::condition_variable wake_;
  bool quit_ = false;
  std::chrono::steady_clock::time_point last_write_;
  std::thread timer_;
};

}  // namespace emlt
