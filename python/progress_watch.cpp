#include "progress_watch.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "emlt/core/interruption.h"

namespace py = pybind11;

namespace emlt::python {

namespace {

// How often the watcher wakes: Ctrl-C is seen within this, and the callback is called at
// this rate.
constexpr auto kWatchInterval = std::chrono::milliseconds(100);

double fraction_of(const ProgressReporter::Status& s) {
  double f = s.total ? double(s.done) / double(s.total) : 0.0;
  if (s.time_limit_s > 0.0) f = std::max(f, s.elapsed_s / s.time_limit_s);
  return std::min(f, 1.0);
}

py::dict status_dict(const ProgressReporter::Status& s) {
  py::dict d;
  d["phase"] = s.label;
  d["done"] = s.done;
  d["total"] = s.total;
  d["fraction"] = fraction_of(s);
  d["elapsed"] = s.elapsed_s;
  d["time_limit"] = s.time_limit_s;
  return d;
}

// A tqdm bar per phase of the render (tqdm.auto: a widget in a notebook).
class TqdmBars {
 public:
  explicit TqdmBars(py::object tqdm) : tqdm_(std::move(tqdm)) {}
  ~TqdmBars() { close(); }

  // `finished`: the render has ended its budget (a time budget's bar is then full).
  void update(const ProgressReporter::Status& s, bool finished) {
    if (s.label.empty()) return;  // not started
    const bool by_time = s.total == 0 && s.time_limit_s > 0.0;
    if (!bar_ || s.label != label_) {
      close();
      label_ = s.label;
      py::object total = by_time   ? py::object(py::float_(s.time_limit_s))
                         : s.total ? py::object(py::int_(s.total))
                                   : py::object(py::none());
      bar_ = tqdm_(py::arg("total") = total, py::arg("desc") = s.label,
                   py::arg("unit") = by_time ? "s" : "", py::arg("leave") = true);
    }
    if (by_time)  // in hundredths of a second: the bar prints n as it is
      bar_.attr("n") = finished ? s.time_limit_s
                                : std::round(std::min(s.elapsed_s, s.time_limit_s) * 100.0) / 100.0;
    else
      bar_.attr("n") = s.done;
    bar_.attr("refresh")();
  }

  void close() {
    if (bar_) bar_.attr("close")();
    bar_ = py::object();
  }

 private:
  py::object tqdm_, bar_;
  std::string label_;
};

}  // namespace

Watched watch_render(const std::function<RenderResult()>& render, const ProgressReporter& reporter,
                     const py::object& progress) {
  py::object callback;
  std::optional<TqdmBars> bars;
  if (PyCallable_Check(progress.ptr())) {
    callback = progress;
  } else if (progress.cast<bool>()) {
    try {
      bars.emplace(py::module_::import("tqdm.auto").attr("tqdm"));
    } catch (const py::error_already_set&) {  // no tqdm: no bar
    }
  }

  Watched watched;
  std::exception_ptr render_error;
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::optional<py::error_already_set> callback_error;
  bool stopping = false;
  const auto stop = [&] {
    stopping = true;
    interruption::request_stop(SIGINT);
  };
  const auto report = [&](bool finished) {
    const ProgressReporter::Status status = reporter.status();
    try {
      if (callback)
        callback(status_dict(status));
      else if (bars)
        bars->update(status, finished);
    } catch (py::error_already_set& e) {
      if (!e.matches(PyExc_KeyboardInterrupt)) callback_error.emplace(std::move(e));
      watched.stopped_by_user = !callback_error;
      stop();
    }
  };

  {
    py::gil_scoped_release release;
    std::thread worker([&] {
      try {
        watched.result = render();
      } catch (...) {
        render_error = std::current_exception();
      }
      std::lock_guard lock(mutex);
      done = true;
      finished.notify_all();
    });
    for (;;) {
      {
        std::unique_lock lock(mutex);
        if (finished.wait_for(lock, kWatchInterval, [&] { return done; })) break;
      }
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {  // Ctrl-C (or another handler's exception)
        py::error_already_set e;
        if (!e.matches(PyExc_KeyboardInterrupt)) callback_error.emplace(std::move(e));
        watched.stopped_by_user = !callback_error;
        stop();
      }
      if (!stopping) report(false);
    }
    worker.join();
  }
  if (render_error) std::rethrow_exception(render_error);
  if (!stopping) report(true);  // the bar at its end
  if (bars) bars->close();
  if (callback_error) throw std::move(*callback_error);
  return watched;
}

}  // namespace emlt::python
