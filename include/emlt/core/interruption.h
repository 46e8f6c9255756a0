#pragma once
// Asking a render to pause: a stop signal (SIGINT, SIGTERM) or a checkpoint falling due.
// Workers poll between paths (pixel samples) and between chain steps, and return as soon as
// the path in hand is done; the integrator then saves or writes what it has
// (render_control.h). The state is process-wide because a signal handler must reach it.
#include <cstdint>
#include <span>
#include <string>

namespace emlt::interruption {

// Whether workers must return now: a stop or a checkpoint was asked for. One relaxed load.
bool requested();

// Called by workers after finishing `units` of work (samples or mutations); returns
// requested(). Counts the units only when a test armed stop_after().
bool poll(uint64_t units);

// From a signal handler (async-signal-safe): the render stops and writes what it has.
void request_stop(int signal);
bool stop_requested();
int stop_signal();  // the first stop signal, 0 if none

// The checkpoint timer's request; cleared once the checkpoint is written.
void request_checkpoint();
bool checkpoint_due();
void clear_checkpoint();

// What to do once the workers have returned (their work done, or cut short by a request):
// with several ranks (cluster.h) the ranks' requests and progress are combined, so every
// rank takes the same decision at the same point, and the local requests are set to the
// union; with one process, this process's own state.
struct Decision {
  bool incomplete = false;  // some rank's share of the pass or sweep is not done
  bool stop = false;        // a stop signal reached some rank: end the render
  bool checkpoint = false;  // a checkpoint fell due on some rank
  bool pause() const { return stop || checkpoint; }
};
// `maxima`: values of the caller's to reduce in the same collective (element-wise maxima,
// on every rank), which saves the caller one: each collective waits for every rank to
// reach it.
Decision agree(bool incomplete, std::span<uint64_t> maxima = {});

// Test hook (EMLT_STOP_AFTER in the command line): stop as if by SIGINT once workers have
// reported this many units of work. 0 disarms it.
void stop_after(uint64_t units);

// The temporary file the calling thread is writing right now (renamed over an output or a
// checkpoint when complete), "" when it has none any more. A second signal removes every
// registered one before the process exits, so the previous files stay untouched and no
// stray temporary is left behind. Each thread has its own registration (a few at once).
void register_temporary(const std::string& path);
// For the signal handler: unlinks the registered temporaries, if any (async-signal-safe).
void remove_temporary();

// Forgets every request (tests that render several times in one process).
void reset();

}  // namespace emlt::interruption
