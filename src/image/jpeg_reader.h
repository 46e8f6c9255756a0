// JPEG decoding with libjpeg(-turbo), the library Mitsuba 0.6 decodes JPEG textures with.
#pragma once

#include <string>

#include "emlt/image/image.h"

namespace emlt {

// Decodes a JPEG file to 8-bit RGB (a grey file expanded to three equal channels), row 0
// at the top. Throws emlt::Error "<path>: <problem>" for a file that is not a JPEG, is
// truncated or corrupt (libjpeg's warnings on damaged data are errors here, as a texture
// with grey holes in it is not what the scene meant), claims an absurd size, or needs a
// colour conversion libjpeg lacks (CMYK).
StoredImage read_jpeg(const std::string& path);

}  // namespace emlt
