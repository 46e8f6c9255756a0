// JPEG through libjpeg rather than stb_image: Debian's stb is built with its asserts on,
// and its JPEG decoder asserts on a malformed Huffman code (an abort, not an error), where
// libjpeg reports every problem through its error manager. libjpeg's default IDCT and
// upsampling are also what Mitsuba 0.6 decodes with, so textures get Mitsuba's texels.
//
// libjpeg reports a fatal error by calling error_exit, which must not return; here it
// jumps back to the setjmp in the function that made the failing call. Only libjpeg's C
// frames lie between the two, and the functions holding a setjmp keep no C++ object alive
// across it, so the jump skips no destructor.
#include "src/image/jpeg_reader.h"

#include <csetjmp>
#include <cstring>

#include "emlt/core/error.h"
#include "src/image/image_file.h"

// jpeglib.h uses FILE and size_t without including their headers.
// clang-format off
#include <cstdio>
#include <jpeglib.h>
#include <jerror.h>
// clang-format on

namespace emlt {

namespace {

// A progressive file may split its coefficients over any number of scans, each of which
// walks the whole image: a small file of many empty scans costs minutes. Real encoders
// write about ten; libjpeg-turbo's own tools suggest refusing more than 500.
constexpr int kMaxProgressiveScans = 500;

struct JpegErrors {
  jpeg_error_mgr manager;  // first, so libjpeg's pointer to it is a pointer to this
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void give_up(j_common_ptr info) {
  auto* errors = reinterpret_cast<JpegErrors*>(info->err);
  info->err->format_message(info, errors->message);
  std::longjmp(errors->jump, 1);
}

// Level -1 is a warning: damaged data that libjpeg would paper over (grey blocks for a
// truncated file, a skipped segment). Stray bytes before a marker change no texel, so
// they pass, as in every viewer; other warnings end the decode. Levels >= 0 are traces.
void on_message(j_common_ptr info, int level) {
  if (level >= 0 || info->err->msg_code == JWRN_EXTRANEOUS_DATA) return;
  give_up(info);
}

void limit_scans(j_common_ptr common) {
  auto* info = reinterpret_cast<j_decompress_ptr>(common);
  if (info->progressive_mode && info->input_scan_number > kMaxProgressiveScans) {
    auto* errors = reinterpret_cast<JpegErrors*>(common->err);
    std::snprintf(errors->message, sizeof(errors->message), "more than %d progressive scans",
                  kMaxProgressiveScans);
    std::longjmp(errors->jump, 1);
  }
}

struct Decompressor {
  jpeg_decompress_struct info{};
  JpegErrors errors{};
  jpeg_progress_mgr progress{};
  // jpeg_destroy_decompress frees nothing for a struct never created (its mem is null).
  ~Decompressor() { jpeg_destroy_decompress(&info); }
};

bool read_header(Decompressor& d, const std::string& bytes) {
  d.info.err = jpeg_std_error(&d.errors.manager);
  d.errors.manager.error_exit = give_up;
  d.errors.manager.emit_message = on_message;
  if (setjmp(d.errors.jump)) return false;
  jpeg_create_decompress(&d.info);
  d.progress.progress_monitor = limit_scans;
  d.info.progress = &d.progress;
  jpeg_mem_src(&d.info, reinterpret_cast<const unsigned char*>(bytes.data()),
               static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&d.info, TRUE);
  d.info.out_color_space = JCS_RGB;
  return true;
}

bool read_pixels(Decompressor& d, unsigned char* rgb) {
  if (setjmp(d.errors.jump)) return false;
  jpeg_start_decompress(&d.info);
  const size_t stride = size_t(d.info.output_width) * 3;
  while (d.info.output_scanline < d.info.output_height) {
    JSAMPROW row = rgb + size_t(d.info.output_scanline) * stride;
    jpeg_read_scanlines(&d.info, &row, 1);
  }
  jpeg_finish_decompress(&d.info);
  return true;
}

}  // namespace

StoredImage read_jpeg(const std::string& path) {
  const std::string bytes = read_file_bytes(path);
  if (bytes.size() < 3 || std::memcmp(bytes.data(), "\xff\xd8\xff", 3) != 0)
    throw file_error(path, "not a JPEG file");

  Decompressor d;
  const auto failure = [&](const char* when) {
    return file_error(path, std::string(when) + " JPEG: " + d.errors.message);
  };
  if (!read_header(d, bytes)) throw failure("cannot read");
  const int64_t width = d.info.image_width, height = d.info.image_height;
  check_image_size(path, width, height);
  // Every 8 x 8 block codes at least one bit (its DC difference), so a file too short for
  // its blocks is truncated: refused before libjpeg fills megabytes of texels with grey.
  const int64_t blocks = (width + 7) / 8 * ((height + 7) / 8);
  if (int64_t(bytes.size()) < blocks / 8) {
    throw file_error(path, "truncated JPEG: " + std::to_string(bytes.size()) +
                               " bytes cannot hold " + std::to_string(width) + " x " +
                               std::to_string(height) + " texels");
  }
  StoredImage image;
  image.width = int(width), image.height = int(height);
  image.channels = d.info.num_components == 1 ? "l" : "rgb";
  image.bytes.resize(size_t(width) * size_t(height) * 3);
  if (!read_pixels(d, image.bytes.data())) throw failure("corrupt");
  return image;
}

}  // namespace emlt
