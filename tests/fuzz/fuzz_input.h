#pragma once
// Shared by the libFuzzer targets: the readers take a file path, so each input is written
// to a file in a directory of this process's own (relative references in a scene resolve
// there), and the reader is called on it. emlt::Error is the readers' deliberate way of
// refusing bad input and counts as a normal outcome; anything else escaping (another
// exception, a crash, a sanitizer report, a leak, a hang) is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "emlt/core/error.h"

namespace emlt::fuzz {

// "<tmp>/emlt-fuzz-<pid>/input<extension>", rewritten with the input's bytes.
inline std::string write_input(const uint8_t* data, size_t size, const std::string& extension) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("emlt-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
#ifdef EMLT_FUZZ_ASSETS
    // Meshes and maps a scene input may name ("assets/panel_uv.obj"), so that the scene
    // loaders go on into the mesh and image readers.
    std::filesystem::copy(EMLT_FUZZ_ASSETS, d / "assets",
                          std::filesystem::copy_options::recursive |
                              std::filesystem::copy_options::overwrite_existing);
#endif
    return d;
  }();
  const std::string path = (dir / ("input" + extension)).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return path;
}

template <class Read>
int run(const uint8_t* data, size_t size, const std::string& extension, Read read) {
  const std::string path = write_input(data, size, extension);
  try {
    read(path);
  } catch (const emlt::Error&) {
    // refused with a message: the expected outcome for malformed input
  }
  return 0;
}

}  // namespace emlt::fuzz
