#pragma once
// Error metrics of an image against a reference, as convergence plots and ablation tables
// report them. All are means over the pixels of a region and over the three channels.
//   mse              mean of (img - ref)^2
//   rel_mse          mean of (img - ref)^2 / (ref^2 + 0.01)   (Rousselle et al.'s relMSE)
//   mse_no_emitter   MSE over pixels that do not see an emitter directly (directly visible
//                    lights are bright and dominate the plain MSE); NaN without a mask
//   mean_ratio       mean(img) / mean(ref): 1 for an unbiased image, up to noise
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "emlt/image/image.h"

namespace emlt {

struct PixelRegion {
  int x = 0, y = 0, width = 0, height = 0;
};

struct ImageMetrics {
  double mse = 0.0, rel_mse = 0.0, mse_no_emitter = 0.0, mean_ratio = 0.0;
  uint64_t pixels = 0, pixels_no_emitter = 0;
};

// Throws emlt::Error when sizes differ or the region lies outside the images.
// `sees_emitter` (optional) has one entry per pixel of the full image.
ImageMetrics compare_images(const Image& reference, const Image& image,
                            const std::optional<PixelRegion>& region = std::nullopt,
                            const std::vector<uint8_t>* sees_emitter = nullptr);

// "x,y,w,h" -> region; throws emlt::Error on malformed text.
PixelRegion parse_pixel_region(const std::string& text);

// False-colour map of the per-pixel relative squared error on a log scale from 1e-4
// (dark blue) to 1 (yellow); pixels outside `region` are grey.
Image relative_error_map(const Image& reference, const Image& image,
                         const std::optional<PixelRegion>& region = std::nullopt);

}  // namespace emlt
