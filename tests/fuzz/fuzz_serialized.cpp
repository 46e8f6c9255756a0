// libFuzzer target: the Mitsuba .serialized mesh reader. Mesh 0 goes through the header
// and the first zlib stream; mesh 1 also through the offset dictionary at the end.
#include "emlt/scene/loaders/serialized_loader.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  emlt::fuzz::run(data, size, ".serialized", [](const std::string& path) {
    emlt::load_serialized_mesh(path, 0, emlt::Mat4(1.0f));
  });
  emlt::fuzz::run(data, size, ".serialized", [](const std::string& path) {
    emlt::load_serialized_mesh(path, 1, emlt::Mat4(1.0f));
  });
  return 0;
}
