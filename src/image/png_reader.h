// PNG decoding with libpng, the library Mitsuba 0.6 reads PNG textures with.
#pragma once

#include <string>

#include "emlt/image/image.h"

namespace emlt {

// Decodes a PNG file as Mitsuba 0.6 reads it: palettes and 1-, 2- and 4-bit grey expanded
// to 8 bits, 16-bit samples kept, grey repeated over three channels, alpha (or a tRNS
// chunk) dropped; the file's curve from its sRGB chunk (sRGB), else its gAMA chunk (the
// exponent 1 / gAMA), else sRGB. Throws emlt::Error "<path>: <problem>" for a file that is
// not a PNG, is truncated or corrupt, or claims an absurd size.
StoredImage read_png(const std::string& path);

}  // namespace emlt
