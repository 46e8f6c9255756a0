#include "image_array.h"

#include <string>

#include "emlt/core/error.h"

namespace py = pybind11;

namespace emlt::python {

py::array_t<float> to_array(Image&& image) {
  static_assert(sizeof(Rgb) == 3 * sizeof(float), "Rgb is three packed floats");
  auto* owned = new Image(std::move(image));
  const py::capsule free_when_done(owned, [](void* p) { delete static_cast<Image*>(p); });
  const auto h = py::ssize_t(owned->height), w = py::ssize_t(owned->width);
  const auto f = py::ssize_t(sizeof(float));
  return py::array_t<float>({h, w, py::ssize_t(3)}, {w * 3 * f, 3 * f, f},
                            reinterpret_cast<const float*>(owned->pixels.data()), free_when_done);
}

Image to_image(const py::handle& object, const char* what) {
  const auto array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!array) throw Error(std::string(what) + ": expected an (H, W, 3) array of numbers");
  if (array.ndim() != 3 || array.shape(2) != 3 || array.shape(0) < 1 || array.shape(1) < 1)
    throw Error(std::string(what) + ": expected an (H, W, 3) array, got shape " +
                std::string(py::str(object.attr("shape"))));
  Image image(int(array.shape(1)), int(array.shape(0)));
  const float* data = array.data();
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = Rgb(data[3 * i], data[3 * i + 1], data[3 * i + 2]);
  return image;
}

}  // namespace emlt::python
