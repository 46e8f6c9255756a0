// Image textures: bilinear filtering, repeat/mirror/clamp wrapping and Mitsuba's uv
// transform. Filtering over the pixel footprint (Mitsuba's EWA) is left to the pixel
// sampler: many point lookups per pixel average the texture over it.
#include <filesystem>
#include <utility>

#include "emlt/core/error.h"
#include "emlt/scene/texture.h"

namespace emlt {
namespace {

bool is_eight_bit_format(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

class BitmapTexture final : public Texture {
 public:
  BitmapTexture(Image image, const UvTransform& transform, WrapMode wrap, std::string name)
      : image_(std::move(image)), transform_(transform), wrap_(wrap), name_(std::move(name)) {}

  Rgb eval(const Vec2& uv) const override {
    const Vec2 p = transform_.apply(uv);
    // Continuous texel coordinates with texel centres at integers.
    const float x = p.x * float(image_.width) - 0.5f;
    const float y = p.y * float(image_.height) - 0.5f;
    if (!std::isfinite(x) || !std::isfinite(y)) return Rgb(0.0f);
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float fx = x - x0, fy = y - y0;
    const int64_t ix = int64_t(x0), iy = int64_t(y0);
    const auto texel = [&](int64_t i, int64_t j) {
      return image_.at(wrap(i, image_.width), wrap(j, image_.height));
    };
    return (1.0f - fy) * ((1.0f - fx) * texel(ix, iy) + fx * texel(ix + 1, iy)) +
           fy * ((1.0f - fx) * texel(ix, iy + 1) + fx * texel(ix + 1, iy + 1));
  }

  std::optional<Rgb> constant() const override {
    if (image_.width == 1 && image_.height == 1) return image_.pixels[0];
    return std::nullopt;
  }

  Vec2 gradient_step() const override {
    return Vec2(1.0f / float(image_.width), 1.0f / float(image_.height)) /
           glm::max(glm::abs(transform_.scale), Vec2(1e-6f));
  }

  std::string name() const override { return name_; }

 private:
  int wrap(int64_t i, int size) const {
    switch (wrap_) {
      case WrapMode::Clamp:
        return int(glm::clamp<int64_t>(i, 0, size - 1));
      case WrapMode::Mirror: {
        const int64_t period = 2 * int64_t(size);
        int64_t m = ((i % period) + period) % period;
        return int(m < size ? m : period - 1 - m);
      }
      case WrapMode::Repeat:
      default:
        return int(((i % size) + size) % size);
    }
  }

  Image image_;
  UvTransform transform_;
  WrapMode wrap_;
  std::string name_;
};

}  // namespace

TexturePtr make_bitmap_texture(Image image, const UvTransform& transform, WrapMode wrap,
                               std::string name) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != size_t(image.width) * size_t(image.height))
    throw Error("bitmap texture '" + name + "' has no pixels");
  return std::make_shared<BitmapTexture>(std::move(image), transform, wrap, std::move(name));
}

TexturePtr load_bitmap_texture(const std::string& path, bool raw, const UvTransform& transform,
                               WrapMode wrap) {
  Image image = read_image(path);
  if (raw && is_eight_bit_format(path)) {
    // read_image decoded the 8-bit values from sRGB; re-encoding returns exactly the
    // stored bytes (the decode is injective on the 256 levels).
    const std::vector<unsigned char> bytes = to_srgb8(image);
    for (size_t i = 0; i < image.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c) image.pixels[i][c] = float(bytes[3 * i + size_t(c)]) / 255.0f;
  }
  return make_bitmap_texture(std::move(image), transform, wrap,
                             std::filesystem::path(path).filename().string());
}

}  // namespace emlt
