// libFuzzer target: the pbrt-v4 tokenizer, parameter lists and scene reader.
#include "emlt/scene/loaders/loader.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return emlt::fuzz::run(data, size, ".pbrt",
                         [](const std::string& path) { emlt::load_pbrt_scene(path); });
}
