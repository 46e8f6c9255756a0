#include "cli/rank_agreement.h"

#include <cstdio>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"

namespace emlt::cli {

namespace {
enum class Phase { Setup, SetupFailedElsewhere, Rendering };
Phase g_phase = Phase::Setup;
}  // namespace

void setup_succeeded() {
  if (cluster::size() == 1) {
    g_phase = Phase::Rendering;
    return;
  }
  g_phase = Phase::SetupFailedElsewhere;
  cluster::agree_on_error("");
  g_phase = Phase::Rendering;
}

std::string settle_error(const std::string& message) {
  if (cluster::size() == 1) return message;
  switch (g_phase) {
    case Phase::Setup:
      g_phase = Phase::SetupFailedElsewhere;
      try {
        cluster::agree_on_error(message);
      } catch (const Error& e) {
        return cluster::is_root() ? e.what() : "";
      }
      return cluster::is_root() ? message : "";
    case Phase::SetupFailedElsewhere:
      return cluster::is_root() ? message : "";
    case Phase::Rendering:
      std::fprintf(stderr, "emlt: error: rank %d: %s\n", cluster::rank(), message.c_str());
      std::fflush(stderr);
      cluster::abort(1);
  }
  return message;
}

}  // namespace emlt::cli
