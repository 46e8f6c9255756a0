#pragma once
// The command line's section of a checkpoint (checkpoint_file.h): the fingerprint of the
// scene's files, every setting that affects the image (by its flag's name, so that a
// mismatch is reported as "checkpoint was made with --max-depth 8, this run has 10"), the
// budget, and the convergence log's rows. Settings that only change how fast or where the
// render goes (threads, the budget, output paths, the checkpoint interval) are left out:
// a render may be resumed with more threads or a larger budget.
#include <string>
#include <utility>
#include <vector>

#include "emlt/scene/description.h"
#include "emlt/settings/settings.h"

namespace emlt {
class ConvergenceLog;
}

namespace emlt::cli {

struct CheckpointHeader {
  uint64_t scene_fingerprint = 0;
  std::vector<std::pair<std::string, std::string>> settings;  // flag, value
  std::string log_header;
  std::vector<std::string> log_rows;

  // What this run is: `defines` as given with -D, the description as loaded.
  static CheckpointHeader describe(const SceneDescription& desc, const RenderSettings& settings,
                                   const std::vector<std::string>& defines);
  std::string encode() const;
  // Throws emlt::Error naming `path` when the section is malformed.
  static CheckpointHeader decode(const std::string& data, const std::string& path);
  // Throws emlt::Error "<path>: checkpoint was made with ..., this run has ..." for the first
  // difference from `now`.
  void check_matches(const CheckpointHeader& now, const std::string& path) const;
};

// FNV-1a over the contents of every input file (a missing one counts by its name).
uint64_t scene_fingerprint(const std::vector<std::string>& files);

}  // namespace emlt::cli
