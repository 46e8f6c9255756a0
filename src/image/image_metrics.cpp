#include "emlt/image/image_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "emlt/core/error.h"

namespace emlt {

namespace {

constexpr double kRelativeEpsilon = 0.01;

PixelRegion whole_or(const Image& image, const std::optional<PixelRegion>& region) {
  if (!region) return {0, 0, image.width, image.height};
  const PixelRegion& r = *region;
  if (r.width <= 0 || r.height <= 0 || r.x < 0 || r.y < 0 || r.x + r.width > image.width ||
      r.y + r.height > image.height)
    throw Error("crop " + std::to_string(r.x) + "," + std::to_string(r.y) + "," +
                std::to_string(r.width) + "," + std::to_string(r.height) + " lies outside the " +
                std::to_string(image.width) + "x" + std::to_string(image.height) + " image");
  return r;
}

double relative_squared_error(const Rgb& ref, const Rgb& img) {
  double sum = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double d = double(img[c]) - ref[c];
    sum += d * d / (double(ref[c]) * ref[c] + kRelativeEpsilon);
  }
  return sum / 3.0;
}

}  // namespace

ImageMetrics compare_images(const Image& reference, const Image& image,
                            const std::optional<PixelRegion>& region,
                            const std::vector<uint8_t>* sees_emitter) {
  if (reference.width != image.width || reference.height != image.height)
    throw Error("image sizes differ: reference " + std::to_string(reference.width) + "x" +
                std::to_string(reference.height) + ", image " + std::to_string(image.width) + "x" +
                std::to_string(image.height));
  const PixelRegion r = whole_or(image, region);
  ImageMetrics m;
  double sum_sq = 0.0, sum_rel = 0.0, sum_sq_no_emitter = 0.0, sum_img = 0.0, sum_ref = 0.0;
  for (int y = r.y; y < r.y + r.height; ++y)
    for (int x = r.x; x < r.x + r.width; ++x) {
      const Rgb& a = reference.at(x, y);
      const Rgb& b = image.at(x, y);
      double sq = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double d = double(b[c]) - a[c];
        sq += d * d;
        sum_img += b[c];
        sum_ref += a[c];
      }
      sq /= 3.0;
      sum_sq += sq;
      sum_rel += relative_squared_error(a, b);
      ++m.pixels;
      if (sees_emitter && !(*sees_emitter)[size_t(y) * image.width + x]) {
        sum_sq_no_emitter += sq;
        ++m.pixels_no_emitter;
      }
    }
  m.mse = sum_sq / double(m.pixels);
  m.rel_mse = sum_rel / double(m.pixels);
  m.mse_no_emitter = sees_emitter && m.pixels_no_emitter
                         ? sum_sq_no_emitter / double(m.pixels_no_emitter)
                         : std::numeric_limits<double>::quiet_NaN();
  m.mean_ratio = sum_ref > 0.0 ? sum_img / sum_ref : std::numeric_limits<double>::quiet_NaN();
  return m;
}

PixelRegion parse_pixel_region(const std::string& text) {
  PixelRegion r;
  char c1 = 0, c2 = 0, c3 = 0;
  std::istringstream in(text);
  if (!(in >> r.x >> c1 >> r.y >> c2 >> r.width >> c3 >> r.height) || c1 != ',' || c2 != ',' ||
      c3 != ',' || !in.eof())
    throw Error("--crop " + text + ": expected x,y,w,h");
  return r;
}

Image relative_error_map(const Image& reference, const Image& image,
                         const std::optional<PixelRegion>& region) {
  compare_images(reference, image, region);  // validates sizes and region
  const PixelRegion r = whole_or(image, region);
  // A perceptually ordered ramp (dark blue -> teal -> green -> yellow).
  static constexpr std::array<Rgb, 5> ramp = {Rgb(0.05f, 0.03f, 0.25f), Rgb(0.10f, 0.25f, 0.55f),
                                              Rgb(0.10f, 0.55f, 0.55f), Rgb(0.35f, 0.80f, 0.30f),
                                              Rgb(0.99f, 0.90f, 0.15f)};
  Image out(image.width, image.height, Rgb(0.2f));
  for (int y = r.y; y < r.y + r.height; ++y)
    for (int x = r.x; x < r.x + r.width; ++x) {
      const double e = relative_squared_error(reference.at(x, y), image.at(x, y));
      const double t = std::clamp((std::log10(std::max(e, 1e-12)) + 4.0) / 4.0, 0.0, 1.0);
      const double pos = t * double(ramp.size() - 1);
      const size_t i = std::min(size_t(pos), ramp.size() - 2);
      const float f = float(pos - double(i));
      // The PNG writer applies the sRGB curve; store linear values of the ramp colours.
      const Rgb srgb = ramp[i] * (1.0f - f) + ramp[i + 1] * f;
      out.at(x, y) = glm::pow(srgb, Rgb(2.2f));
    }
  return out;
}

}  // namespace emlt
