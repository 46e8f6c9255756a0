#pragma once
#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

#include "cli/render_job.h"

namespace emlt::cli {

struct RenderOptions {
  std::string scene, output;
  std::string integrator;
  int width = 0, height = 0;
  // The text given to each declared render option (render_options()), by flag.
  std::map<std::string, std::string> option_text;
  std::vector<std::string> defines;
  std::string reference, log;
  // --checkpoint FILE, written every checkpoint_interval seconds and on a stop signal;
  // --resume FILE continues from one (and keeps checkpointing into it).
  std::string checkpoint, resume;
  double checkpoint_interval = 600.0;
  bool quiet = false;
  bool strict = false;  // refuse a scene emlt would approximate or partly ignore
  bool bvh_only = false;  // no direct triangle tests on small scenes (SceneBuildOptions)
};

struct InfoOptions {
  std::string scene;
  std::vector<std::string> defines;
  bool strict = false;
  bool json = false;  // warnings with their kinds, for tools (tools/conformance/coverage_matrix.py)
};

void add_render_options(CLI::App& command, RenderOptions& options);
int run_render(const CLI::App& command, RenderOptions& options);
// What a parsed `emlt render` command line asks for: the options given, and only those.
RenderRequest render_request(const CLI::App& command, const RenderOptions& options);
// Writes the image to `output` and, unless it is a PNG, its PNG preview beside it; returns
// what was written ("out.exr + out.png").
std::string write_render_image(const std::string& output, const Image& image);
int run_info(const InfoOptions& options);

// "name=value" strings into a map; throws emlt::Error on a malformed entry.
std::map<std::string, std::string> parse_defines(const std::vector<std::string>& defines);

}  // namespace emlt::cli
