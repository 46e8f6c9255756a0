#pragma once
// A render from Python runs on its own thread while the interpreter's thread watches it:
// it calls the progress callback (or draws a tqdm bar) and checks for Ctrl-C, which only
// the interpreter's main thread can see. Ctrl-C, or KeyboardInterrupt raised by the
// callback, asks the render to stop as the command line's SIGINT does: it finishes the
// paths in hand, writes its checkpoint if it has one, and returns its image normalised for
// the work done.
#include <pybind11/pybind11.h>

#include <functional>

#include "emlt/run/integrator.h"
#include "emlt/run/progress.h"

namespace emlt::python {

struct Watched {
  RenderResult result;
  bool stopped_by_user = false;  // Ctrl-C or KeyboardInterrupt from the callback
};

// Called with the GIL held; releases it while `render` runs. `progress`: a callable taking a
// dict (phase, done, total, fraction, elapsed, time_limit), True (a tqdm bar, when tqdm is
// installed) or False. An exception from `render` is rethrown, and so is one the callback
// raises other than KeyboardInterrupt (once the render has stopped).
Watched watch_render(const std::function<RenderResult()>& render, const ProgressReporter& reporter,
                     const pybind11::object& progress);

}  // namespace emlt::python
