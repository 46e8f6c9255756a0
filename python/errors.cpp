// emlt::Error, the engine's one-line refusals (a range, a file, a checkpoint that does not
// match), as emlt.Error: a ValueError, so that `except ValueError` catches a bad argument,
// with the command line's words.
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "emlt/core/error.h"

namespace emlt::python {

void bind_errors(pybind11::module_& m) {
  pybind11::register_exception<emlt::Error>(m, "Error", PyExc_ValueError);
}

}  // namespace emlt::python
