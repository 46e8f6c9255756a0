// PNG through libpng rather than stb_image: Mitsuba reads a PNG's gAMA chunk (a file
// written with gAMA 1.0 is linear to Mitsuba, sRGB to stb's users) and keeps 16-bit
// samples, which stb_image's 8-bit interface rounds; and libpng reports every problem
// through its error callback, where Debian's stb is built with its asserts on.
//
// libpng reports a fatal error through the error callback, which must not return; here it
// jumps back to the setjmp in the function that made the failing call. Only libpng's C
// frames lie between the two, and the functions holding a setjmp keep no C++ object alive
// across it, so the jump skips no destructor.
#include "src/image/png_reader.h"

#include <png.h>

#include <bit>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "emlt/core/error.h"
#include "src/image/image_file.h"

namespace emlt {
namespace {

struct PngFailure {
  std::jmp_buf jump;
  char message[256];
};

[[noreturn]] void give_up(png_structp png, png_const_charp message) {
  auto* failure = static_cast<PngFailure*>(png_get_error_ptr(png));
  std::snprintf(failure->message, sizeof(failure->message), "%s", message);
  std::longjmp(failure->jump, 1);
}

// Warnings concern ancillary data (a colour profile libpng thinks wrong, a damaged text
// chunk, which libpng skips): the texels are whole, as Mitsuba, which logs them, reads them.
void ignore_warning(png_structp, png_const_charp) {}

struct MemoryReader {
  const std::string* bytes;
  size_t at;
};

void read_from_memory(png_structp png, png_bytep out, size_t length) {
  auto* reader = static_cast<MemoryReader*>(png_get_io_ptr(png));
  if (length > reader->bytes->size() - reader->at) png_error(png, "file ends early");
  std::memcpy(out, reader->bytes->data() + reader->at, length);
  reader->at += length;
}

struct Decompressor {
  png_structp png = nullptr;
  png_infop info = nullptr;
  PngFailure failure{};
  MemoryReader reader{};
  ~Decompressor() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

// The header, and the transformations that turn every colour type into RGB, or RGBA when
// the file has alpha (8 or 16 bits a sample, 16-bit ones in the machine's byte order).
// `channels`: the file's channels as Mitsuba names them (a tRNS chunk is alpha).
bool read_header(Decompressor& d, png_uint_32* width, png_uint_32* height, int* bits, int* passes,
                 float* gamma, std::string* channels) {
  if (setjmp(d.failure.jump)) return false;
  png_set_read_fn(d.png, &d.reader, read_from_memory);
  png_read_info(d.png, d.info);
  int colour = 0;
  png_get_IHDR(d.png, d.info, width, height, bits, &colour, nullptr, nullptr, nullptr);
  if (colour == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(d.png);
  if (*bits < 8) png_set_expand_gray_1_2_4_to_8(d.png);  // (palettes are 8-bit once expanded)
  if (*bits == 16 && std::endian::native == std::endian::little) png_set_swap(d.png);
  const bool transparency = png_get_valid(d.png, d.info, PNG_INFO_tRNS) != 0;
  if (transparency) png_set_tRNS_to_alpha(d.png);
  const bool grey = colour == PNG_COLOR_TYPE_GRAY || colour == PNG_COLOR_TYPE_GRAY_ALPHA;
  const bool alpha = transparency || (colour & PNG_COLOR_MASK_ALPHA) != 0;
  *channels = grey ? (alpha ? "ya" : "l") : (alpha ? "rgba" : "rgb");
  if (grey) png_set_gray_to_rgb(d.png);
  int intent = 0;
  double file_gamma = 0.0;
  if (png_get_sRGB(d.png, d.info, &intent))
    *gamma = kSrgbGamma;
  else if (png_get_gAMA(d.png, d.info, &file_gamma) && file_gamma > 0.0)
    *gamma = float(1.0 / file_gamma);
  else
    *gamma = kSrgbGamma;
  // Interlaced files need every pass over every row (png_read_row, pass by pass).
  *passes = png_set_interlace_handling(d.png);
  png_read_update_info(d.png, d.info);
  *bits = png_get_bit_depth(d.png, d.info);
  if (png_get_channels(d.png, d.info) != (alpha ? 4 : 3))
    png_error(d.png, "unexpected channel count");
  return true;
}

bool read_rows(Decompressor& d, unsigned char* data, size_t stride, png_uint_32 height,
               int passes) {
  if (setjmp(d.failure.jump)) return false;
  for (int pass = 0; pass < passes; ++pass)
    for (png_uint_32 y = 0; y < height; ++y) png_read_row(d.png, data + y * stride, nullptr);
  png_read_end(d.png, nullptr);
  return true;
}

// RGBA samples into RGB and alpha.
template <class Sample>
void split_alpha(const std::vector<Sample>& rgba, std::vector<Sample>& rgb,
                 std::vector<Sample>& alpha) {
  const size_t texels = rgba.size() / 4;
  rgb.resize(texels * 3);
  alpha.resize(texels);
  for (size_t i = 0; i < texels; ++i) {
    rgb[3 * i] = rgba[4 * i], rgb[3 * i + 1] = rgba[4 * i + 1], rgb[3 * i + 2] = rgba[4 * i + 2];
    alpha[i] = rgba[4 * i + 3];
  }
}

}  // namespace

StoredImage read_png(const std::string& path) {
  const std::string bytes = read_file_bytes(path);
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0)
    throw file_error(path, "not a PNG file");

  Decompressor d;
  d.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &d.failure, give_up, ignore_warning);
  if (d.png) d.info = png_create_info_struct(d.png);
  if (!d.png || !d.info) throw file_error(path, "cannot set up the PNG decoder");
  d.reader = {&bytes, 0};

  png_uint_32 width = 0, height = 0;
  int bits = 8, passes = 1;
  StoredImage image;
  if (!read_header(d, &width, &height, &bits, &passes, &image.gamma, &image.channels))
    throw file_error(path, std::string("cannot read PNG: ") + d.failure.message);
  check_image_size(path, width, height);
  image.width = int(width), image.height = int(height);
  // Without alpha the rows go straight into the image; with it, through an RGBA buffer.
  const size_t texels = size_t(width) * size_t(height);
  const size_t samples = image.channels.back() == 'a' ? 4 : 3;
  const auto decode = [&](auto& colour, auto& alpha) {
    using Sample = typename std::decay_t<decltype(colour)>::value_type;
    std::vector<Sample> rgba;
    std::vector<Sample>& rows = samples == 4 ? rgba : colour;
    rows.resize(texels * samples);
    if (!read_rows(d, reinterpret_cast<unsigned char*>(rows.data()),
                   size_t(width) * samples * sizeof(Sample), height, passes))
      throw file_error(path, std::string("corrupt PNG: ") + d.failure.message);
    if (samples == 4) split_alpha(rgba, colour, alpha);
  };
  if (bits == 16)
    decode(image.words, image.alpha_words);
  else
    decode(image.bytes, image.alpha_bytes);
  return image;
}

}  // namespace emlt
