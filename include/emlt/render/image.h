#pragma once
// A float RGB image, and reading/writing it by file extension. Writes are atomic: the data
// goes to a temporary file in the same directory which is then renamed over the target, so
// a crash never leaves a truncated image behind.
#include <array>
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

// Reads .exr (OpenEXR, RGB or Y channels), .hdr (Radiance), .pfm, .png/.jpg (sRGB decoded
// to linear). Throws emlt::Error "<path>: <problem>" on a missing/malformed file or on
// NaN/Inf texels.
Image read_image(const std::string& path);

// An 8-bit file (.png, .jpg) as it stores its texels: 3 bytes per pixel (RGB, a grey or
// alpha file expanded as read_image expands it), row-major, row 0 at the top. read_image
// decodes byte b of such a file to srgb8_levels()[b].
struct Image8 {
  int width = 0, height = 0;
  std::vector<unsigned char> bytes;
};
bool is_eight_bit_image(const std::string& path);  // by extension
// Throws as read_image does (and for a file of another format).
Image8 read_image8(const std::string& path);
const std::array<float, 256>& srgb8_levels();

// Writes by extension: .exr (half-free float RGB), .pfm, .png (tone-mapped sRGB preview),
// .hdr. Throws emlt::Error for an unknown extension or an I/O failure.
void write_image(const std::string& path, const Image& image);

// Path of the PNG preview written beside an EXR/PFM/HDR render ("cornell.exr" ->
// "cornell.png").
std::string preview_path_for(const std::string& path);

// Linear -> sRGB 8-bit with clamping (exposure multiplies before the transfer curve).
std::vector<unsigned char> to_srgb8(const Image& image, float exposure = 1.0f);

}  // namespace emlt
