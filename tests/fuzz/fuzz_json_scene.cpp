// libFuzzer target: the native JSON scene loader (meshes and maps it names resolve in the
// input's own directory).
#include "emlt/scene/loaders/loader.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return emlt::fuzz::run(data, size, ".json",
                         [](const std::string& path) { emlt::load_json_scene(path); });
}
