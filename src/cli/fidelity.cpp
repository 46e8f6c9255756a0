#include "cli/fidelity.h"

#include "emlt/core/error.h"

namespace emlt::cli {

void refuse_divergences_if_strict(const SceneDescription& desc, bool strict) {
  if (!strict || desc.divergences.empty()) return;
  const size_t more = desc.divergences.size() - 1;
  // The message already names the file and line.
  throw Error(desc.divergences.front().message + " (refused by --strict" +
              (more ? "; " + std::to_string(more) + " more such items" : std::string()) + ")");
}

std::string divergence_summary(const SceneDescription& desc) {
  if (desc.divergences.empty()) return "";
  return desc.source + ": not rendered exactly as its format means: " + desc.verdict() +
         " (listed above; --strict refuses such scenes)";
}

}  // namespace emlt::cli
