#pragma once
// Ctrl-C and SIGTERM during `emlt render`. The first one asks the render to stop
// (interruption.h): it finishes the paths in hand, writes its checkpoint and its image
// normalised for the work done, and the command exits with 128 + the signal's number. A
// second one means "now": the process exits at once, removing the temporary file being
// written (if any), so the previous output or checkpoint stays as it was.
namespace emlt::cli {

// Installs the handlers for SIGINT and SIGTERM.
void handle_stop_signals();

// 128 + the signal that stopped the render (130 for SIGINT, 143 for SIGTERM).
int exit_status_for_stop();

// "SIGINT", "SIGTERM".
const char* stop_signal_name();

}  // namespace emlt::cli
