// emlt.compare(reference, image): `emlt compare`'s metrics, with the images as numpy arrays
// (or file names), so that no file is needed.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <optional>
#include <string>

#include "bindings.h"
#include "cli/compare_command.h"
#include "emlt/core/error.h"
#include "emlt/image/image_metrics.h"
#include "image_array.h"

namespace py = pybind11;

namespace emlt::python {

namespace {

Image image_from(const py::handle& object, const char* what) {
  if (py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__"))
    return read_image(py::str(py::module_::import("os").attr("fspath")(object)));
  return to_image(object, what);
}

// "x,y,w,h" or (x, y, w, h), as --crop takes it.
std::optional<PixelRegion> region_of(const py::object& crop) {
  if (crop.is_none()) return std::nullopt;
  std::string text;
  if (py::isinstance<py::str>(crop))
    text = crop.cast<std::string>();
  else
    for (const py::handle value : crop)
      text += (text.empty() ? "" : ",") + std::string(py::str(value));
  return parse_pixel_region(text);
}

py::dict compare(const py::object& reference, const py::object& image, const py::object& crop,
                 const py::object& scene) {
  const Image ref = image_from(reference, "reference");
  const Image img = image_from(image, "image");
  const std::optional<PixelRegion> region = region_of(crop);
  std::vector<uint8_t> mask;
  std::string scene_path;
  if (!scene.is_none())
    scene_path = py::hasattr(scene, "path") ? scene.attr("path").cast<std::string>()
                                            : py::str(scene).cast<std::string>();
  ImageMetrics m;
  {
    py::gil_scoped_release release;
    if (!scene_path.empty()) mask = cli::visible_emitter_mask(scene_path, ref.width, ref.height);
    m = compare_images(ref, img, region, mask.empty() ? nullptr : &mask);
  }
  py::dict d;
  d["mse"] = m.mse;
  d["relmse"] = m.rel_mse;
  d["mse_no_emitter"] = std::isnan(m.mse_no_emitter) ? py::object(py::none())
                                                     : py::object(py::float_(m.mse_no_emitter));
  d["mean_ratio"] = m.mean_ratio;
  d["pixels"] = m.pixels;
  return d;
}

py::array_t<float> error_map(const py::object& reference, const py::object& image,
                             const py::object& crop) {
  const Image ref = image_from(reference, "reference");
  const Image img = image_from(image, "image");
  const std::optional<PixelRegion> region = region_of(crop);
  Image map;
  {
    py::gil_scoped_release release;
    map = relative_error_map(ref, img, region);
  }
  return to_array(std::move(map));
}

}  // namespace

void bind_compare(py::module_& m) {
  m.def("error_map", &error_map, py::arg("reference"), py::arg("image"), py::kw_only(),
        py::arg("crop") = py::none(),
        "The false-colour relative-error image of `emlt compare --error-map`, as an (H, W, 3)\n"
        "float32 array.");
  m.def("compare", &compare, py::arg("reference"), py::arg("image"), py::kw_only(),
        py::arg("crop") = py::none(), py::arg("scene") = py::none(),
        "The metrics of `emlt compare` (mse, relmse, mse_no_emitter, mean_ratio, pixels) of\n"
        "`image` against `reference`: (H, W, 3) arrays or image files. crop: 'x,y,w,h' or\n"
        "(x, y, w, h); scene: an emlt.Scene or scene file, for the MSE over the pixels that\n"
        "see no emitter (None without it, as `emlt compare --json` gives null).");
}

}  // namespace emlt::python
