#pragma once
// The parts of the `emlt` Python module, each bound by its own file; module.cpp calls them.
#include <pybind11/pybind11.h>

namespace emlt::python {

void bind_errors(pybind11::module_& m);   // emlt.Error (a ValueError): every refusal
void bind_scene(pybind11::module_& m);    // emlt.Scene, emlt.load
void bind_render(pybind11::module_& m);   // emlt.render
void bind_compare(pybind11::module_& m);  // emlt.compare

}  // namespace emlt::python
