#pragma once
#include <string>

#include "emlt/integrators/mlt/mlt_integrator.h"

namespace emlt::cli {

// The per-strategy table on stderr, and (when path is set) the same as JSON, written
// atomically.
// `name`: the integrator (mlt, gamlt, emlt) that the printed lines start with.
void report_mlt_statistics(const std::string& name, const MltStatistics& stats,
                           const std::string& json_path);

}  // namespace emlt::cli
