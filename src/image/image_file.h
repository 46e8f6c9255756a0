// What every image reader shares (image_io.cpp, png_reader.cpp, jpeg_reader.cpp): the
// largest image it accepts, and the file's bytes.
#pragma once

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>

#include "emlt/core/error.h"

namespace emlt {

// Every reader checks the size its header claims against these before it allocates or
// decodes anything, so a corrupt or hostile header cannot ask for gigabytes. 2^28 texels
// are 3 GiB as float RGB, and a reader may hold a second copy while it converts: 16384 x
// 16384 (the largest film) and 32768 x 8192 still fit; 2^29 would let one header take
// 6 GiB or more.
constexpr int64_t kMaxImageSide = 65536;
constexpr int64_t kMaxImageTexels = int64_t(1) << 28;

inline void check_image_size(const std::string& path, int64_t width, int64_t height) {
  if (width <= 0 || height <= 0) throw file_error(path, "image has zero size");
  // The sides first, so that their product cannot overflow.
  if (width > kMaxImageSide || height > kMaxImageSide || width * height > kMaxImageTexels)
    throw file_error(path, "header claims " + std::to_string(width) + " x " +
                               std::to_string(height) +
                               " texels; images may have at most 65536 texels a side and "
                               "2^28 (about 268 million) in all");
}

// The whole file; an error names it when it cannot be read.
inline std::string read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.is_open() || in.bad()) throw file_error(path, "cannot read the file");
  return bytes;
}

}  // namespace emlt
