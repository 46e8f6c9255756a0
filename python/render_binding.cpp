// emlt.render(scene, integrator=None, **options) -> (image, stats): the command line's render.
// The keywords are written as the command line's flags (max_depth=5 is --max-depth=5) and
// parsed by `emlt render`'s own parser, so every option is there under its own name and a
// bad value is refused in the command line's words; the render is the command line's
// render job (src/cli/render_job.h), so the image is the command line's, bit for bit.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.h"
#include "cli/commands.h"
#include "cli/mlt_report.h"
#include "cli/readable_range.h"
#include "cli/render_job.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "image_array.h"
#include "progress_watch.h"
#include "scene_handle.h"

namespace py = pybind11;

namespace emlt::python {

namespace {

// A keyword's value as the text its flag takes on the command line.
std::string option_text(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value) || py::isinstance<py::str>(value)) return py::str(value);
  if (py::isinstance<py::float_>(value)) return py::repr(value);  // shortest round trip
  if (py::hasattr(value, "__fspath__"))
    return py::str(py::module_::import("os").attr("fspath")(value));
  throw py::type_error("render(): " + name + " must be a number, a string or a path, not " +
                       std::string(py::str(value.get_type().attr("__name__"))));
}

// `emlt render SCENE --flag=value ...` from the keywords. The flag=value form keeps a
// negative number a value.
std::vector<std::string> command_line(const SceneHandle& scene, const py::object& integrator,
                                      const py::kwargs& kwargs, CLI::App& render) {
  std::vector<std::string> args = {"emlt", "render", scene.path};
  for (const std::string& define : scene.defines) args.insert(args.end(), {"-D", define});
  if (!integrator.is_none())
    args.push_back("--integrator=" + option_text("integrator", integrator));
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    std::string flag = "--" + name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    const CLI::Option* option = render.get_option_no_throw(flag);
    if (name.find('-') != std::string::npos || !option || flag == "--help")
      throw py::type_error("render() got an unexpected keyword argument '" + name +
                           "' (emlt render has no option " + flag + ")");
    if (value.is_none()) continue;       // as if not given
    if (option->get_type_size() == 0) {  // a flag: --strict, --bvh-only, --quiet
      if (!py::isinstance<py::bool_>(value))
        throw py::type_error("render(): " + name + " must be True or False");
      if (value.cast<bool>()) args.push_back(flag);
      continue;
    }
    args.push_back(flag + "=" + option_text(name, value));
  }
  return args;
}

SceneHandle scene_of(const py::object& scene) {
  if (py::isinstance<SceneHandle>(scene)) return scene.cast<SceneHandle>();
  SceneHandle handle;  // a file name: the file with no defines
  handle.path = py::str(py::module_::import("os").attr("fspath")(scene));
  return handle;
}

py::tuple render(const py::object& scene_arg, const py::object& integrator,
                 const py::object& progress, const py::kwargs& kwargs) {
  // The stop requests are the process's (a signal handler must reach them), so one render
  // at a time: another thread's render would take this one's stop for its own.
  static std::mutex one_render;
  const std::unique_lock<std::mutex> rendering(one_render, std::try_to_lock);
  if (!rendering.owns_lock())
    throw std::runtime_error("emlt.render: another render is running in this process");
  const SceneHandle scene = scene_of(scene_arg);
  CLI::App app;
  cli::RenderOptions options;
  CLI::App* command = app.add_subcommand("render");
  cli::add_render_options(*command, options);
  const std::vector<std::string> args = command_line(scene, integrator, kwargs, *command);
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  try {
    app.parse(int(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    throw Error(cli::readable_parse_error(e.what()));
  }
  cli::RenderRequest request = cli::render_request(*command, options);
  request.progress = false;  // no bar on stderr: the callback or tqdm draws one

  std::vector<std::string> warnings;
  std::unique_ptr<cli::RenderJob> job;
  {
    py::gil_scoped_release release;
    job = std::make_unique<cli::RenderJob>(std::move(request),
                                           [&](const std::string& w) { warnings.push_back(w); });
  }
  for (const std::string& w : warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();

  // Each render starts without a stop request, and leaves none behind.
  interruption::reset();
  ProgressReporter reporter(false);
  Watched watched;
  try {
    watched = watch_render([&] { return job->run(reporter); }, reporter, progress);
  } catch (...) {
    interruption::reset();
    throw;
  }
  interruption::reset();
  RenderResult& result = watched.result;

  const RenderSettings& settings = job->settings();
  py::dict stats;
  stats["integrator"] = job->integrator().name();
  stats["width"] = result.image.width;
  stats["height"] = result.image.height;
  stats["seconds"] = result.seconds;
  stats["samples"] = result.samples;
  stats["samples_per_pixel"] = result.samples_per_pixel;
  stats["mcmc"] = job->mcmc();
  if (job->mcmc())
    stats["mutations_per_pixel"] =
        double(result.samples) / (double(result.image.width) * result.image.height);
  stats["invalid_samples"] = result.invalid_samples;
  stats["interrupted"] = result.interrupted;
  if (result.interrupted) {
    stats["per_pixel"] = result.per_pixel;  // the work done when it stopped
    stats["stopped_in"] =
        result.stopped_in.empty() ? py::object(py::none()) : py::object(py::str(result.stopped_in));
  }
  if (!job->checkpoint_path().empty()) {
    stats["checkpoint"] = job->checkpoint_path();
    stats["checkpoints_written"] = job->checkpoints_written();
  }
  stats["warnings"] = warnings;
  // The chains' figures, as --stats writes them (an MCMC integrator's).
  if (const auto* chains = dynamic_cast<const ChainStatisticsSource*>(&job->integrator()))
    stats["chains"] = py::module_::import("json").attr("loads")(
        cli::mlt_statistics_json(chains->chain_statistics()).dump());
  std::optional<ImageMetrics> against;
  {
    py::gil_scoped_release release;
    against = job->against_reference(result.image);
    if (!job->request().output.empty())
      cli::write_render_image(job->request().output, result.image);
    if (!settings.stats_path.empty())
      if (const auto* chains = dynamic_cast<const ChainStatisticsSource*>(&job->integrator()))
        cli::report_mlt_statistics(settings.integrator, chains->chain_statistics(),
                                   settings.stats_path);
  }
  if (against) {
    py::dict d;
    d["mse"] = against->mse;
    d["relmse"] = against->rel_mse;
    d["mse_no_emitter"] = against->mse_no_emitter;
    d["mean_ratio"] = against->mean_ratio;
    stats["reference"] = d;
  }
  return py::make_tuple(to_array(std::move(result.image)), stats);
}

// Every keyword render() takes, with its flag and the command line's help for it.
py::dict keywords() {
  CLI::App app;
  cli::RenderOptions options;
  CLI::App* command = app.add_subcommand("render");
  cli::add_render_options(*command, options);
  py::dict d;
  for (const CLI::Option* option : command->get_options()) {
    const std::vector<std::string>& long_names = option->get_lnames();
    if (long_names.empty() || long_names.front() == "help") continue;
    std::string keyword = long_names.front();
    std::replace(keyword.begin(), keyword.end(), '-', '_');
    d[py::str(keyword)] = py::make_tuple("--" + long_names.front(), option->get_description());
  }
  return d;
}

}  // namespace

void bind_render(py::module_& m) {
  m.def("keywords", &keywords,
        "Every option of emlt.render as {keyword: (flag, help)}, from `emlt render`'s own list.");
  m.def("render", &render, py::arg("scene"), py::arg("integrator") = py::none(), py::kw_only(),
        py::arg("progress") = true,
        "Renders `scene` (an emlt.Scene or a scene file) as `emlt render` does and returns\n"
        "(image, stats): an (H, W, 3) float32 array and a dict of the render's figures.\n\n"
        "Every option of `emlt render` is a keyword, named as its flag: spp=64 (--spp 64),\n"
        "mpp=16, time=30.0, seed=2, threads=4, max_depth=5, checkpoint='run.ckpt',\n"
        "resume='run.ckpt', reference='ref.exr', strict=True, ...; a value the command line\n"
        "refuses raises emlt.Error (a ValueError) in its words.\n"
        "progress: a callable given a dict (phase, done, total, fraction, elapsed,\n"
        "time_limit) about every 0.1 s, True (a tqdm bar when tqdm is installed) or False.\n"
        "output='out.exr' also writes the image (and its PNG preview), as the command line.\n"
        "Ctrl-C, or KeyboardInterrupt raised by the callback, stops the render: it returns\n"
        "what was done, normalised, with stats['interrupted'] True.");
}

}  // namespace emlt::python
