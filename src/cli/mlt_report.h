#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "emlt/integrators/mlt/mlt_integrator.h"

namespace emlt::cli {

// The per-strategy table on stderr, and (when path is set) the same as JSON, written
// atomically.
// `name`: the integrator (mlt, gamlt, emlt) that the printed lines start with.
void report_mlt_statistics(const std::string& name, const MltStatistics& stats,
                           const std::string& json_path);
// The figures as --stats writes them (b with its error, the chains, each strategy's counts).
nlohmann::json mlt_statistics_json(const MltStatistics& stats);

}  // namespace emlt::cli
