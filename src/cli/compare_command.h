#pragma once
#include <CLI/CLI.hpp>

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

}  // namespace emlt::cli
