// Image textures: bilinear filtering, repeat/mirror/clamp wrapping and Mitsuba's uv
// transform. Filtering over the pixel footprint (Mitsuba's EWA) is left to the pixel
// sampler: many point lookups per pixel average the texture over it.
#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <utility>
#include <vector>

#include "emlt/core/error.h"
#include "emlt/scene/loaders/load_prefetch.h"
#include "emlt/scene/texture.h"

namespace emlt {
namespace {

// Texels of an 8-bit file as the file stores them: one byte per channel and the 256 float
// levels the bytes decode to. A quarter of float RGB's memory (the public Veach door's
// textures take 5.5 MB instead of 22 MB), and every lookup returns exactly the float that
// read_image decoded, so renders keep their bits.
struct EightBitTexels {
  std::vector<uint8_t> bytes;  // 3 per texel, row-major like Image::pixels
  std::array<float, 256> levels{};
};

// A thread's recent lookups, direct-mapped by texture and uv. The queries made at one
// surface point ask for the same texels again and again: a path tracer's light sample and
// then its BSDF sample; a bidirectional vertex's walk step and its connections to every
// vertex of the other subpath (value and both densities each time); the vertices an MLT
// mutation keeps. A lookup is a pure function of the texture and the uv, so a value found
// here is bit for bit the value computed again, whatever the thread or the order.
// Entries are keyed by a serial number that no other texture of the process ever gets,
// not by address: a texture freed and another made at its address (the next scene loaded
// in the same process) must not find the first one's values. Plain data, zero-initialised
// (serial 0 is nobody's), so that the thread_local needs no guard.
struct LookupCache {
  static constexpr unsigned kBits = 6;
  struct Entry {
    uint64_t texture;
    uint32_t u, v;  // the uv's bits
    float value[3];
  };
  Entry entries[1u << kBits];

  static unsigned slot(uint64_t texture, uint32_t u, uint32_t v) {
    const uint32_t h = (u * 0x9E3779B1u) ^ (v * 0x85EBCA77u) ^ uint32_t(texture * 0xC2B2AE35u);
    return (h ^ (h >> 15)) & ((1u << kBits) - 1u);
  }
  static uint64_t next_serial() {
    static std::atomic<uint64_t> last{0};
    return last.fetch_add(1, std::memory_order_relaxed) + 1;
  }
};
// initial-exec: emlt's engine is linked into its programs, and the general TLS model
// would call __tls_get_addr on every lookup. Not in an engine built for the Python module
// (EMLT_SHARED_ENGINE): a module loaded by dlopen finds no room for 2 KB in the static TLS
// block ("cannot allocate memory in static TLS block"), and in the programs the linker
// turns the general model into the same direct access.
#if defined(EMLT_SHARED_ENGINE)
thread_local LookupCache lookup_cache;
#else
[[gnu::tls_model("initial-exec")]] thread_local LookupCache lookup_cache;
#endif

class BitmapTexture final : public Texture {
 public:
  BitmapTexture(Image image, const UvTransform& transform, TextureWrap wrap, std::string name)
      : width_(image.width),
        height_(image.height),
        image_(std::move(image)),
        transform_(transform),
        wrap_(wrap),
        name_(std::move(name)) {}

  BitmapTexture(int width, int height, EightBitTexels texels, const UvTransform& transform,
                TextureWrap wrap, std::string name)
      : width_(width),
        height_(height),
        eight_bit_(std::move(texels)),
        transform_(transform),
        wrap_(wrap),
        name_(std::move(name)) {}

  Rgb eval(const Vec2& uv) const override {
    const uint32_t u_bits = std::bit_cast<uint32_t>(uv.x), v_bits = std::bit_cast<uint32_t>(uv.y);
    LookupCache::Entry& entry = lookup_cache.entries[LookupCache::slot(serial_, u_bits, v_bits)];
    if (entry.texture == serial_ && entry.u == u_bits && entry.v == v_bits)
      return Rgb(entry.value[0], entry.value[1], entry.value[2]);
    const Rgb value = filtered(uv);
    entry = LookupCache::Entry{serial_, u_bits, v_bits, {value.x, value.y, value.z}};
    return value;
  }

  std::optional<Rgb> constant() const override {
    if (width_ == 1 && height_ == 1) return at(0, 0);
    return std::nullopt;
  }

  Vec2 gradient_step() const override {
    return Vec2(1.0f / float(width_), 1.0f / float(height_)) /
           glm::max(glm::abs(transform_.scale), Vec2(1e-6f));
  }

  std::string name() const override { return name_; }

 private:
  // Bilinear filtering of the four texels around uv.
  Rgb filtered(const Vec2& uv) const {
    const Vec2 p = transform_.apply(uv);
    // Continuous texel coordinates with texel centres at integers.
    const float x = p.x * float(width_) - 0.5f;
    const float y = p.y * float(height_) - 0.5f;
    if (!std::isfinite(x) || !std::isfinite(y)) return Rgb(0.0f);
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float fx = x - x0, fy = y - y0;
    const int64_t ix = int64_t(x0), iy = int64_t(y0);
    // Each of the two columns and rows is wrapped once (the four texels share them).
    const int left = wrap(ix, width_, wrap_.u), right = wrap_next(ix, left, width_, wrap_.u);
    const int top = wrap(iy, height_, wrap_.v), bottom = wrap_next(iy, top, height_, wrap_.v);
    // One test for the four texels: only Zero and One give an index below 0.
    if ((left | right | top | bottom) >= 0)
      return (1.0f - fy) * ((1.0f - fx) * texel(left, top) + fx * texel(right, top)) +
             fy * ((1.0f - fx) * texel(left, bottom) + fx * texel(right, bottom));
    return (1.0f - fy) * ((1.0f - fx) * at(left, top) + fx * at(right, top)) +
           fy * ((1.0f - fx) * at(left, bottom) + fx * at(right, bottom));
  }

  // Indices wrap() gives a texel outside the image under Zero and One.
  static constexpr int kZeroTexel = -1, kOneTexel = -2;

  // A texel or, under Zero and One, the constant outside the image; the u axis decides
  // first, as in Mitsuba's MIP map.
  Rgb at(int x, int y) const {
    if (x < 0) return Rgb(x == kZeroTexel ? 0.0f : 1.0f);
    if (y < 0) return Rgb(y == kZeroTexel ? 0.0f : 1.0f);
    return texel(x, y);
  }

  Rgb texel(int x, int y) const {
    const size_t i = size_t(y) * size_t(width_) + size_t(x);
    if (!eight_bit_) return image_.pixels[i];
    const uint8_t* b = &eight_bit_->bytes[3 * i];
    const std::array<float, 256>& level = eight_bit_->levels;
    return Rgb(level[b[0]], level[b[1]], level[b[2]]);
  }

  // wrap(i + 1, size) given wrapped = wrap(i, size): under Repeat the next texel of a
  // tiled texture is the wrapped one's neighbour, with no second division.
  static int wrap_next(int64_t i, int wrapped, int size, WrapMode mode) {
    if (mode == WrapMode::Repeat) return wrapped + 1 == size ? 0 : wrapped + 1;
    return wrap(i + 1, size, mode);
  }

  static int wrap(int64_t i, int size, WrapMode mode) {
    // Inside the image every mode leaves the index as it is, and a lookup's texels mostly
    // are: skip the 64-bit divisions, which cost more than the rest of the lookup.
    if (i >= 0 && i < size) return int(i);
    switch (mode) {
      case WrapMode::Zero:
        return kZeroTexel;
      case WrapMode::One:
        return kOneTexel;
      case WrapMode::Clamp:
        return int(glm::clamp<int64_t>(i, 0, size - 1));
      case WrapMode::Mirror: {
        const int64_t period = 2 * int64_t(size);
        int64_t m = ((i % period) + period) % period;
        return int(m < size ? m : period - 1 - m);
      }
      case WrapMode::Repeat:
      default:
        // A 32-bit division where the index allows (a texture repeated a few times): a
        // fraction of a 64-bit one's latency, and the texel's address waits on it.
        if (i >= INT32_MIN && i <= INT32_MAX) {
          const int32_t m = int32_t(i) % size;
          return m < 0 ? m + size : m;
        }
        return int(((i % size) + size) % size);
    }
  }

  const uint64_t serial_ = LookupCache::next_serial();  // this texture's key in lookup_cache
  int width_, height_;
  Image image_;                              // float texels, empty when eight_bit_ holds them
  std::optional<EightBitTexels> eight_bit_;  // texels of an 8-bit file
  UvTransform transform_;
  TextureWrap wrap_;
  std::string name_;
};

}  // namespace

TexturePtr make_bitmap_texture(Image image, const UvTransform& transform, TextureWrap wrap,
                               std::string name) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != size_t(image.width) * size_t(image.height))
    throw Error("bitmap texture '" + name + "' has no pixels");
  return std::make_shared<BitmapTexture>(std::move(image), transform, wrap, std::move(name));
}

TexturePtr load_bitmap_texture(const std::string& path, std::optional<float> gamma,
                               const UvTransform& transform, TextureWrap wrap,
                               const std::string& channel) {
  std::string name = std::filesystem::path(path).filename().string();
  if (!channel.empty() && !is_stored_image(path))
    throw file_error(path, "a channel of a float image cannot be chosen (only of PNG and JPEG)");
  if (!is_stored_image(path)) {
    Image image = read_image(path);
    // A float file is linear; a gamma given for it bends its values all the same, as
    // Mitsuba's does.
    if (gamma && *gamma != 1.0f) {
      for (Rgb& texel : image.pixels)
        texel = Rgb(decode_gamma(texel.x, *gamma), decode_gamma(texel.y, *gamma),
                    decode_gamma(texel.z, *gamma));
    }
    return make_bitmap_texture(std::move(image), transform, wrap, name);
  }
  // The file's own samples, never decoded to floats and encoded back (that round trip was
  // a third of loading the public Veach door's textures). Sample v of an 8-bit file reads
  // as the level the curve gives v / 255; a 16-bit PNG is decoded to floats.
  std::optional<StoredImage> prefetched = LoadPrefetch::stored_image(path);
  StoredImage image = prefetched ? std::move(*prefetched) : read_stored_image(path);
  if (!channel.empty()) {
    image = select_channel(std::move(image), channel, path);
    if (image.channels == "a") gamma.reset();  // alpha stays linear (select_channel)
  }
  const float curve = gamma.value_or(image.gamma);
  if (!image.words.empty())
    return make_bitmap_texture(decode_stored_image(image, curve), transform, wrap, name);
  EightBitTexels texels;
  texels.bytes = std::move(image.bytes);
  texels.levels = levels8(curve);
  return std::make_shared<BitmapTexture>(image.width, image.height, std::move(texels), transform,
                                         wrap, std::move(name));
}

}  // namespace emlt
