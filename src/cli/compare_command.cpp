// `emlt compare REF IMG...`: error metrics of images against a reference.
#include "cli/compare_command.h"

#include <fmt/core.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "emlt/core/error.h"
#include "emlt/image/image_metrics.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"
#include "emlt/scene/visible_emitters.h"

namespace emlt::cli {

void add_compare_options(CLI::App& command, CompareOptions& o) {
  command.add_option("reference", o.reference, "Reference image")->required();
  command.add_option("images", o.images, "Images to compare")->required();
  command.add_flag("--json", o.json, "Print one JSON object per image");
  command.add_option("--error-map", o.error_map,
                     "Write a false-colour relative-error PNG (one image only)");
  command.add_option("--crop", o.crop, "Restrict the metrics to x,y,w,h");
  command.add_option("--scene", o.scene,
                     "Scene the images show: enables MSE over pixels that see no emitter");
}

std::vector<uint8_t> visible_emitter_mask(const std::string& scene, int width, int height) {
  SceneDescription desc = load_scene_description(scene, {});
  // The scene's image is its film, or its crop window: resized to the reference otherwise.
  CameraDesc& camera = desc.camera;
  if (!(camera.cropped() && camera.crop_width == width && camera.crop_height == height)) {
    camera.width = width;
    camera.height = height;
    camera.crop_width = camera.crop_height = 0;
  }
  return directly_visible_emitters(*Scene::build(std::move(desc)));
}

int run_compare(const CompareOptions& o) {
  if (!o.error_map.empty() && o.images.size() != 1)
    throw Error("--error-map takes exactly one image to compare");
  const Image reference = read_image(o.reference);
  const std::optional<PixelRegion> region =
      o.crop.empty() ? std::nullopt : std::optional(parse_pixel_region(o.crop));

  const std::vector<uint8_t> mask = o.scene.empty()
                                       ? std::vector<uint8_t>()
                                       : visible_emitter_mask(o.scene, reference.width,
                                                              reference.height);

  if (!o.json)
    fmt::print("{:<32} {:>12} {:>12} {:>14} {:>10}\n", "image", "mse", "relmse", "mse_no_emitter",
               "mean_ratio");
  for (const std::string& path : o.images) {
    const Image image = read_image(path);
    ImageMetrics m;
    try {
      m = compare_images(reference, image, region, mask.empty() ? nullptr : &mask);
    } catch (const Error& e) {
      throw file_error(path, e.what());
    }
    if (o.json) {
      nlohmann::json j = {{"image", path}, {"reference", o.reference}, {"mse", m.mse},
                          {"relmse", m.rel_mse}, {"mean_ratio", m.mean_ratio}, {"pixels", m.pixels}};
      j["mse_no_emitter"] = std::isnan(m.mse_no_emitter) ? nlohmann::json(nullptr)
                                                         : nlohmann::json(m.mse_no_emitter);
      fmt::print("{}\n", j.dump());
    } else {
      fmt::print("{:<32} {:>12.6g} {:>12.6g} {:>14.6g} {:>10.5f}\n", path, m.mse, m.rel_mse,
                 m.mse_no_emitter, m.mean_ratio);
    }
  }
  if (!o.error_map.empty()) {
    write_image(o.error_map, relative_error_map(reference, read_image(o.images[0]), region));
    if (!o.json) fmt::print("error map -> {}\n", o.error_map);
  }
  return 0;
}

}  // namespace emlt::cli
