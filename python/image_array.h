#pragma once
// Images between the engine and numpy: an (H, W, 3) float32 array, row 0 at the top, as
// emlt's files store them.
#include <pybind11/numpy.h>

#include "emlt/image/image.h"

namespace emlt::python {

// The array takes the image's pixels over (no copy): it owns them until Python frees it.
pybind11::array_t<float> to_array(Image&& image);

// An (H, W, 3) array of numbers (any float or integer dtype) as an image; throws
// emlt::Error "<what>: ..." for any other shape.
Image to_image(const pybind11::handle& array, const char* what);

}  // namespace emlt::python
