// The `emlt` command: render, info, compare. Every user-facing failure is one line on stderr
// ("emlt: error: <file>: <problem>") and a non-zero exit; no partial output file is left.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli/commands.h"
#include "cli/compare_command.h"
#include "cli/rank_agreement.h"
#include "cli/readable_range.h"
#include "emlt/core/cluster.h"
#include "emlt/core/error.h"

namespace {

// The error line, once per run (rank 0 under MPI, rank_agreement.h).
int fail(const std::string& message, int status) {
  const std::string line = emlt::cli::settle_error(message);
  if (!line.empty()) std::fprintf(stderr, "emlt: error: %s\n", line.c_str());
  return status;
}

int run(int argc, char** argv) {
  CLI::App app{"emlt: Monte Carlo and Markov chain Monte Carlo light transport"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "emlt 0.1.0");

  emlt::cli::RenderOptions render_options;
  CLI::App* render = app.add_subcommand("render", "Render a scene to an image");
  emlt::cli::add_render_options(*render, render_options);

  emlt::cli::InfoOptions info_options;
  CLI::App* info = app.add_subcommand("info", "Print what a scene file contains");
  info->add_option("scene", info_options.scene, "Scene file (.json or Mitsuba .xml)")->required();
  info->add_option("-D", info_options.defines, "Scene parameter, name=value (repeatable)");
  info->add_flag("--strict", info_options.strict,
                 "Fail if the scene uses anything emlt approximates or cannot honour");
  info->add_flag("--json", info_options.json,
                 "Print the warnings, each with its kind (note, approximated, unsupported), "
                 "and the verdict as one JSON object");

  emlt::cli::CompareOptions compare_options;
  CLI::App* compare = app.add_subcommand("compare", "Error metrics of images against a reference");
  emlt::cli::add_compare_options(*compare, compare_options);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return emlt::cluster::is_root() ? app.exit(e) : 0;
    return fail(emlt::cli::readable_parse_error(e.what()), 2);
  }

  try {
    if (*render) return emlt::cli::run_render(*render, render_options);
    // Under MPI only rank 0 answers the commands that do not render.
    if (!emlt::cluster::is_root()) return 0;
    if (*info) return emlt::cli::run_info(info_options);
    if (*compare) return emlt::cli::run_compare(compare_options);
  } catch (const std::exception& e) {  // emlt::Error and everything else: one line
    return fail(e.what(), 1);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  emlt::cluster::init(&argc, &argv);
  const int status = run(argc, argv);
  emlt::cluster::finalize();
  return status;
}
