// libFuzzer target: the OBJ mesh loader, smooth (computed or file normals) on inputs of
// odd size, flat on even.
#include <vector>

#include "emlt/scene/loaders/obj_loader.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return emlt::fuzz::run(data, size, ".obj", [size](const std::string& path) {
    std::vector<std::string> warnings;
    emlt::load_obj_mesh(path, emlt::Mat4(1.0f), size % 2 == 1, &warnings);
  });
}
