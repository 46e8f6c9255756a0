// emlt.load(path, **defines) -> emlt.Scene: the scene as `emlt info` reads it, with the
// loader's verdict and warnings as Python objects. A render reads the file again, as the
// command line does, so that it is the command line's render.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <map>
#include <string>
#include <vector>

#include "bindings.h"
#include "cli/commands.h"
#include "emlt/integrators/registry.h"
#include "emlt/run/scene_settings.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"
#include "scene_handle.h"

namespace py = pybind11;

namespace emlt::python {

namespace {

// A define's value as the command line's -D name=value would give it.
std::string define_text(const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::float_>(value)) return py::repr(value);
  return py::str(value);
}

SceneHandle load(const py::object& path, const py::kwargs& kwargs) {
  SceneHandle handle;
  handle.path = py::str(py::module_::import("os").attr("fspath")(path));
  for (const auto& [name, value] : kwargs)
    handle.defines.push_back(py::str(name).cast<std::string>() + "=" + define_text(value));
  py::gil_scoped_release release;
  SceneDescription desc = load_scene_description(handle.path, cli::parse_defines(handle.defines));
  RenderSettings settings = settings_for(desc.render);
  apply_integrator_options(desc.render, settings);
  handle.integrator = settings.integrator;
  const auto scene = Scene::build(std::move(desc));
  const SceneDescription& d = scene->description();
  handle.width = scene->camera().width();
  handle.height = scene->camera().height();
  handle.verdict = d.verdict();
  // Each warning with its kind, as `emlt info --json` gives them.
  std::vector<bool> matched(d.divergences.size(), false);
  for (const std::string& warning : scene->warnings()) {
    std::string kind = "note";
    for (size_t i = 0; i < d.divergences.size(); ++i) {
      if (matched[i] || d.divergences[i].message != warning) continue;
      matched[i] = true;
      kind =
          d.divergences[i].kind == Divergence::Kind::Approximated ? "approximated" : "unsupported";
      break;
    }
    handle.warnings.push_back({kind, warning});
  }
  return handle;
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<SceneHandle>(m, "Scene",
                          "A scene file as emlt.load read it; emlt.render(scene, ...) renders it.")
      .def_readonly("path", &SceneHandle::path)
      .def_property_readonly(
          "defines",
          [](const SceneHandle& s) {
            std::map<std::string, std::string> d;
            for (const std::string& text : s.defines) {
              const size_t eq = text.find('=');
              d[text.substr(0, eq)] = text.substr(eq + 1);
            }
            return d;
          },
          "The defines given to load(), as the text -D gives")
      .def_readonly("verdict", &SceneHandle::verdict,
                    "'exact', or the items emlt approximates or cannot honour")
      .def_property_readonly(
          "warnings",
          [](const SceneHandle& s) {
            py::list list;
            for (const auto& [kind, message] : s.warnings) {
              py::dict w;
              w["kind"] = kind;
              w["message"] = message;
              list.append(w);
            }
            return list;
          },
          "Each warning as {'kind': 'note' | 'approximated' | 'unsupported', 'message': ...}")
      .def_readonly("width", &SceneHandle::width)
      .def_readonly("height", &SceneHandle::height)
      .def_readonly("integrator", &SceneHandle::integrator,
                    "The integrator the file asks for (else the engine's default)")
      .def("__repr__", [](const SceneHandle& s) {
        return "<emlt.Scene " + s.path + " " + std::to_string(s.width) + "x" +
               std::to_string(s.height) + ", " + s.integrator + ", " + s.verdict + ">";
      });
  m.def("load", &load, py::arg("path"),
        "Reads a scene file (Mitsuba 0.6/3 XML or emlt JSON); keywords are its defines, as\n"
        "-D name=value gives them. Raises emlt.Error (a ValueError) on a file emlt refuses.");
}

}  // namespace emlt::python
