#include "cli/mlt_report.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "emlt/core/atomic_write.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"

namespace emlt::cli {

void report_mlt_statistics(const std::string& name, const MltStatistics& st,
                           const std::string& json_path) {
  // b's samples: the bootstrap's, and any drawn beside the chains; pssmlt's and mmlt's, the
  // seeds' primary samples and the chains' large steps.
  char samples[160];
  if (st.b_large_steps > 0 && st.b_bidirectional_samples > 0)
    std::snprintf(samples, sizeof samples,
                  "%llu samples: %llu the seeds', %llu large steps, %llu BDPT; the largest %.2g "
                  "of b",
                  static_cast<unsigned long long>(st.b_samples),
                  static_cast<unsigned long long>(st.b_samples - st.b_large_steps -
                                                  st.b_bidirectional_samples),
                  static_cast<unsigned long long>(st.b_large_steps),
                  static_cast<unsigned long long>(st.b_bidirectional_samples), st.b_largest_share);
  else if (st.b_large_steps > 0)
    std::snprintf(samples, sizeof samples,
                  "%llu samples: %llu the seeds', %llu large steps; the largest %.2g of b",
                  static_cast<unsigned long long>(st.b_samples),
                  static_cast<unsigned long long>(st.b_samples - st.b_large_steps),
                  static_cast<unsigned long long>(st.b_large_steps), st.b_largest_share);
  else if (st.b_samples > st.bootstrap_samples)
    std::snprintf(samples, sizeof samples,
                  "%llu samples: %llu bootstrap, %llu beside the chains; the largest %.2g of b",
                  static_cast<unsigned long long>(st.b_samples),
                  static_cast<unsigned long long>(st.bootstrap_samples),
                  static_cast<unsigned long long>(st.b_samples - st.bootstrap_samples),
                  st.b_largest_share);
  else
    std::snprintf(samples, sizeof samples, "%llu bootstrap samples",
                  static_cast<unsigned long long>(st.bootstrap_samples));
  std::fprintf(
      stderr, "%s: b = %.6g +- %.2g (%s), %llu chains, %llu mutations, %.3f M mutations/s\n",
      name.c_str(), st.b, st.b_standard_error, samples, static_cast<unsigned long long>(st.chains),
      static_cast<unsigned long long>(st.mutations),
      st.seconds > 0.0 ? double(st.mutations) / st.seconds * 1e-6 : 0.0);
  // The searches some strategies build before the chains (gamlt's), when they took any time.
  char prepared[64] = "";
  if (st.prepare_seconds >= 0.0005)
    std::snprintf(prepared, sizeof prepared, ", %.3f s building searches before them",
                  st.prepare_seconds);
  // The separate direct light and the samples beside the chains, where the run had them
  // (erpt has neither: its seeds deposit the direct light).
  char direct[64] = "", beside[64] = "";
  if (st.direct_spp > 0)
    std::snprintf(direct, sizeof direct, "%.3f s direct light (%d spp), ", st.direct_seconds,
                  st.direct_spp);
  if (st.normalisation_seconds > 0.0)
    std::snprintf(beside, sizeof beside, "%.3f s normalisation beside the chains, ",
                  st.normalisation_seconds);
  std::fprintf(stderr, "  time: %s%.3f s bootstrap, %schains alone %.3f M mutations/s%s\n", direct,
               st.bootstrap_seconds, beside, st.chain_mutations_per_second() * 1e-6, prepared);
  if (st.ensemble_size > 0)
    std::fprintf(stderr,
                 "  ensembles: 2 x %llu paths, M = %llu guides, %llu steps per path between swaps, "
                 "%llu swaps, "
                 "%.3f s building trees, mean alpha %.3f\n",
                 static_cast<unsigned long long>(st.ensemble_size),
                 static_cast<unsigned long long>(st.ensemble_neighbours),
                 static_cast<unsigned long long>(st.ensemble_iterations),
                 static_cast<unsigned long long>(st.swaps), st.tree_seconds, st.mean_alpha);
  if (st.alpha.total() > 0)
    std::fprintf(stderr,
                 "  alpha over %llu guided stretches: min %.3f, quartiles %.3f / %.3f / %.3f, "
                 "max %.3f\n",
                 static_cast<unsigned long long>(st.alpha.total()), st.alpha.min,
                 st.alpha.quantile(0.25), st.alpha.quantile(0.5), st.alpha.quantile(0.75),
                 st.alpha.max);
  // A render stopped before its chains began has no strategy figures: a table of zeros would
  // read like a measurement.
  const bool chains_ran = st.mutations > 0;
  if (chains_ran)
    std::fprintf(stderr, "  %-16s %12s %14s %12s %12s %10s %10s\n", "strategy", "proposed",
                 "not applicable", "failed", "accepted", "mean a", "fallbacks");
  for (size_t i = 0; i < st.strategies.size(); ++i) {
    const StrategyStats& s = st.strategies[i];
    // MMLT lists every path length up to the depth limit; one the chains never reached says
    // nothing.
    if (chains_ran && s.proposed + s.not_applicable > 0)
      std::fprintf(stderr, "  %-16s %12llu %14llu %12llu %12llu %10.4f %10llu\n",
                   st.strategy_names[i].c_str(), static_cast<unsigned long long>(s.proposed),
                   static_cast<unsigned long long>(s.not_applicable),
                   static_cast<unsigned long long>(s.failed),
                   static_cast<unsigned long long>(s.accepted), s.mean_acceptance(),
                   static_cast<unsigned long long>(s.fallbacks));
  }
  if (!json_path.empty())
    write_file_atomically(json_path, "statistics", mlt_statistics_json(st).dump(2) + "\n");
}

nlohmann::json mlt_statistics_json(const MltStatistics& st) {
  nlohmann::json strategies = nlohmann::json::array();
  for (size_t i = 0; i < st.strategies.size(); ++i) {
    const StrategyStats& s = st.strategies[i];
    strategies.push_back({{"name", st.strategy_names[i]},
                          {"proposed", s.proposed},
                          {"not_applicable", s.not_applicable},
                          {"failed", s.failed},
                          {"accepted", s.accepted},
                          {"mean_acceptance", s.mean_acceptance()},
                          {"fallbacks", s.fallbacks}});
  }
  nlohmann::json j = {
      {"b", st.b},
      {"b_standard_error", st.b_standard_error},
      {"bootstrap_samples", st.bootstrap_samples},
      {"bootstrap_b", st.bootstrap_b},
      {"b_samples", st.b_samples},
      {"b_largest_share", st.b_largest_share},
      {"b_large_steps", st.b_large_steps},
      {"b_bidirectional_samples", st.b_bidirectional_samples},
      {"normalisation_seconds", st.normalisation_seconds},
      {"chains", st.chains},
      {"mutations", st.mutations},
      {"seconds", st.seconds},
      {"mutations_per_second", st.seconds > 0.0 ? double(st.mutations) / st.seconds : 0.0},
      {"chain_mutations_per_second", st.chain_mutations_per_second()},
      {"direct_seconds", st.direct_seconds},
      {"direct_spp", st.direct_spp},
      {"bootstrap_seconds", st.bootstrap_seconds},
      {"prepare_seconds", st.prepare_seconds},
      {"strategies", strategies}};
  // Known only to the run that made the pool (a resumed run does not save it).
  if (st.bootstrap_effective_candidates > 0.0)
    j["bootstrap_effective_candidates"] = st.bootstrap_effective_candidates;
  if (st.ensemble_size > 0)
    j["ensemble"] = {{"size", st.ensemble_size},
                     {"neighbours", st.ensemble_neighbours},
                     {"iterations", st.ensemble_iterations},
                     {"swaps", st.swaps},
                     {"tree_seconds", st.tree_seconds},
                     {"mean_alpha", st.mean_alpha}};
  // α's distribution over the guided stretches (quartiles to 1/256).
  if (st.ensemble_size > 0 && st.alpha.total() > 0)
    j["ensemble"]["alpha"] = {{"steps", st.alpha.total()},     {"min", st.alpha.min},
                              {"q1", st.alpha.quantile(0.25)}, {"median", st.alpha.quantile(0.5)},
                              {"q3", st.alpha.quantile(0.75)}, {"max", st.alpha.max},
                              {"mean", st.alpha.mean()}};
  return j;
}

}  // namespace emlt::cli
