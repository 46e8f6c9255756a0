// libFuzzer target: the PLY mesh loader (ASCII and binary).
#include <vector>

#include "emlt/scene/loaders/ply_loader.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return emlt::fuzz::run(data, size, ".ply", [](const std::string& path) {
    std::vector<std::string> warnings;
    emlt::load_ply_mesh(path, emlt::Mat4(1.0f), &warnings);
  });
}
