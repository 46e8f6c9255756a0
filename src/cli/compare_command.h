#pragma once
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace emlt::cli {

struct CompareOptions {
  std::string reference;
  std::vector<std::string> images;
  std::string error_map, crop, scene;
  bool json = false;
};

void add_compare_options(CLI::App& command, CompareOptions& options);
int run_compare(const CompareOptions& options);

// One entry per pixel of a width x height image of `scene` (its film, or its crop window of
// that size): whether the pixel sees an emitter directly, for the metrics' "mse without
// visible emitters".
std::vector<uint8_t> visible_emitter_mask(const std::string& scene, int width, int height);

}  // namespace emlt::cli
