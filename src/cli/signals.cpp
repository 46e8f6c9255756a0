#include "cli/signals.h"

#include <unistd.h>

#include <csignal>

#include "emlt/core/interruption.h"

namespace emlt::cli {

namespace {

extern "C" void on_stop_signal(int signal) {
  if (interruption::stop_requested()) {
    interruption::remove_temporary();
    ::_exit(128 + signal);
  }
  interruption::request_stop(signal);
}

}  // namespace

void handle_stop_signals() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int exit_status_for_stop() {
  const int signal = interruption::stop_signal();
  return 128 + (signal > 0 ? signal : SIGINT);
}

const char* stop_signal_name() {
  return interruption::stop_signal() == SIGTERM ? "SIGTERM" : "SIGINT";
}

}  // namespace emlt::cli
