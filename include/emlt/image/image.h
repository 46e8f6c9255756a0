#pragma once
// A float RGB image, and reading/writing it by file extension. Writes are atomic: the data
// goes to a temporary file in the same directory which is then renamed over the target, so
// a crash never leaves a truncated image behind.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "emlt/core/math.h"

namespace emlt {

struct Image {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;  // row-major, row 0 at the top

  Image() = default;
  Image(int w, int h, Rgb fill = Rgb(0.0f)) : width(w), height(h), pixels(size_t(w) * h, fill) {}
  Rgb& at(int x, int y) { return pixels[size_t(y) * width + x]; }
  const Rgb& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
};

// A file's transfer curve in Mitsuba's convention (its Bitmap gamma): kSrgbGamma for the
// sRGB curve, otherwise the exponent g that takes a stored value v in [0, 1] to v^g (1:
// linear). PNG and JPEG files are sRGB unless a PNG's gAMA chunk (and no sRGB chunk) gives
// its own exponent; float formats are linear.
constexpr float kSrgbGamma = -1.0f;
// Stored value -> linear value (a power curve takes negative values to 0).
float decode_gamma(float value, float gamma);

// Reads .exr (OpenEXR, RGB or Y channels), .hdr (Radiance), .pfm, .png/.jpg (decoded to
// linear by the file's own curve). Throws emlt::Error "<path>: <problem>" on a
// missing/malformed file or on NaN/Inf texels.
Image read_image(const std::string& path);

// A PNG or JPEG file as it stores its texels, as Mitsuba 0.6 reads them (libpng, libjpeg):
// 3 samples per pixel (RGB; a grey file's value repeated, palettes expanded, alpha kept
// apart below), row-major, row 0 at the top; 8-bit samples in `bytes`, or a 16-bit PNG's in
// `words` (then `bytes` is empty). read_image decodes each sample v / max by `gamma`.
struct StoredImage {
  int width = 0, height = 0;
  std::vector<unsigned char> bytes;
  std::vector<uint16_t> words;
  float gamma = kSrgbGamma;  // the file's own curve
  // The file's channels as Mitsuba names them: "l" (grey), "ya" (grey and alpha), "rgb" or
  // "rgba" (a PNG's tRNS chunk counts as alpha); the alpha samples, one per texel, in
  // alpha_bytes or alpha_words (as bytes or words hold the colour), when it has alpha.
  std::string channels = "rgb";
  std::vector<unsigned char> alpha_bytes;
  std::vector<uint16_t> alpha_words;
};
// The image with one of its channels (a name from `channels`) in all three samples of each
// texel, as Mitsuba's bitmap `channel` reads it; alpha is linear whatever the file's curve.
// Throws emlt::Error naming `path` and the channels there are when it has no such channel.
StoredImage select_channel(StoredImage image, const std::string& channel, const std::string& path);
// Linear float RGB from the stored samples under `gamma` (read_image passes the file's own).
Image decode_stored_image(const StoredImage& image, float gamma);
bool is_stored_image(const std::string& path);  // by extension: .png, .jpg, .jpeg
// Throws as read_image does (and for a file of another format).
StoredImage read_stored_image(const std::string& path);
// The linear values of the 256 levels of an 8-bit sample under `gamma`.
std::array<float, 256> levels8(float gamma);
const std::array<float, 256>& srgb8_levels();  // levels8(kSrgbGamma), computed once

// Writes by extension: .exr (half-free float RGB), .pfm, .png (tone-mapped sRGB preview),
// .hdr. Throws emlt::Error for an unknown extension or an I/O failure.
void write_image(const std::string& path, const Image& image);

// Path of the PNG preview written beside an EXR/PFM/HDR render ("cornell.exr" ->
// "cornell.png").
std::string preview_path_for(const std::string& path);

// Linear -> sRGB 8-bit with clamping (exposure multiplies before the transfer curve).
std::vector<unsigned char> to_srgb8(const Image& image, float exposure = 1.0f);

}  // namespace emlt
