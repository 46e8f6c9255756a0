// libFuzzer target: the Mitsuba 0.6 XML parser and scene loader.
#include "emlt/scene/loaders/loader.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return emlt::fuzz::run(data, size, ".xml",
                         [](const std::string& path) { emlt::load_mitsuba_scene(path); });
}
