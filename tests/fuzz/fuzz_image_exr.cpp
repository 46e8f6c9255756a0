// libFuzzer target: read_image on a .exr file.
#include "emlt/image/image.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return emlt::fuzz::run(data, size, ".exr", [](const std::string& path) { emlt::read_image(path); });
}
