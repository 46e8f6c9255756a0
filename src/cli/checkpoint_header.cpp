#include "cli/checkpoint_header.h"

#include <fmt/core.h>

#include <fstream>
#include <iterator>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/state_io.h"

namespace emlt::cli {

uint64_t scene_fingerprint(const std::vector<std::string>& files) {
  uint64_t hash = fnv1a64("emlt scene");
  for (const std::string& file : files) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
      hash = fnv1a64("missing:" + file, hash);
      continue;
    }
    const std::string contents((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    hash = fnv1a64(contents, hash);
  }
  return hash;
}

CheckpointHeader CheckpointHeader::describe(const SceneDescription& desc,
                                            const RenderSettings& s,
                                            const std::vector<std::string>& defines) {
  CheckpointHeader h;
  h.scene_fingerprint = cli::scene_fingerprint(desc.input_files);
  const auto number = [](auto v) { return fmt::format("{}", v); };
  const auto add = [&](const char* flag, std::string value) { h.settings.emplace_back(flag, std::move(value)); };
  add("--integrator", s.integrator);
  add("mpirun -n", number(cluster::size()));  // each rank's share depends on the count
  add("--width", number(desc.camera.width));
  add("--height", number(desc.camera.height));
  add("--seed", number(s.seed));
  add("--max-depth", number(s.max_depth));
  add("--rr-depth", number(s.rr_depth));
  add("--mis", to_string(s.mis));
  add("--direct-samples", number(s.direct_samples));
  add("--direct-sampler", s.direct_point_set == DirectPointSet::Fibonacci ? "fibonacci" : "independent");
  add("--chains", s.chains > 0 ? number(s.chains) : "(from the budget)");
  // Only the path-space MLT family grows its pool (mlt_integrator.cpp).
  const bool grows = s.bootstrap_grows &&
                     (s.integrator == "mlt" || s.integrator == "gamlt" || s.integrator == "emlt");
  add("--bootstrap", number(s.bootstrap_samples) + (grows ? " (grown as needed)" : ""));
  add("--bootstrap-seed", s.bootstrap_seed ? number(*s.bootstrap_seed) : "(--seed)");
  add("--mutations", s.mutations.empty() ? "(the integrator's own)" : s.mutations);
  add("--direct", s.direct_separate ? "separate" : "mlt");
  add("--mlt-splat", s.mlt_expected_values ? "expected" : "state");
  add("--gamlt-cone", s.gamlt_field_cone         ? "field"
                      : s.gamlt_cone_cells > 0.0 ? "cells (" + number(s.gamlt_cone_cells) + ")"
                                                 : "exact");
  add("--gamlt-acceptance", s.gamlt_delayed_acceptance ? "delayed" : "full");
  add("--direct-spp", s.direct_spp > 0 ? number(s.direct_spp) : "(from the budget)");
  add("--ensemble-size", number(s.ensemble_size));
  add("--ensemble-neighbours", number(s.ensemble_neighbours));
  add("--ensemble-iterations", number(s.ensemble_iterations));
  add("--ensemble-alpha", number(s.ensemble_alpha));
  add("--ensemble-similarity-length", number(s.ensemble_similarity_length));
  add("--ensemble-aniso-fallback", s.ensemble_plane_fallback ? "plane" : "vmf");
  add("--ensemble-aniso-scale", number(s.ensemble_aniso_scale));
  add("--ensemble-aniso-multiscale", number(s.ensemble_aniso_smallest_scale));
  add("--ensemble-aniso-covariance", s.ensemble_aniso_weighted ? "weighted" : "printed");
  add("--ensemble-guides", s.ensemble_nearby_guides ? "nearby" : "counter");
  add("--ensemble-alpha-from", s.ensemble_alpha_from_ensemble ? "ensemble" : "guides");
  add("--pss-tracer", s.pss_bdpt ? "bdpt" : "pt");
  add("--large-step", number(s.large_step_probability));
  add("--pss-sigma", number(s.pss_sigma));
  add("--bdpt-strategies", s.bdpt_strategies_dir.empty() ? "(none)" : "(a folder)");
  add("--aniso-map", s.aniso_map_path.empty() ? "(none)" : "(a file)");
  std::string joined;
  for (const std::string& d : defines) joined += (joined.empty() ? "" : " ") + d;
  add("-D", joined.empty() ? "(none)" : joined);
  return h;
}

std::string CheckpointHeader::encode() const {
  StateWriter out;
  out.put(scene_fingerprint);
  out.put<uint64_t>(settings.size());
  for (const auto& [flag, value] : settings) {
    out.put_string(flag);
    out.put_string(value);
  }
  out.put_string(log_header);
  out.put<uint64_t>(log_rows.size());
  for (const std::string& row : log_rows) out.put_string(row);
  return out.take();
}

CheckpointHeader CheckpointHeader::decode(const std::string& data, const std::string& path) {
  try {
    StateReader in(data);
    CheckpointHeader h;
    h.scene_fingerprint = in.get<uint64_t>();
    const uint64_t count = in.get<uint64_t>();
    if (count > 1000) throw StateError("too many settings");
    for (uint64_t i = 0; i < count; ++i) {
      std::string flag = in.get_string();
      h.settings.emplace_back(std::move(flag), in.get_string());
    }
    h.log_header = in.get_string();
    const uint64_t rows = in.get<uint64_t>();
    if (rows > in.remaining()) throw StateError("too many log rows");
    for (uint64_t i = 0; i < rows; ++i) h.log_rows.push_back(in.get_string());
    in.expect_end();
    return h;
  } catch (const StateError& e) {
    throw file_error(path, std::string("checkpoint is malformed: ") + e.what());
  }
}

void CheckpointHeader::check_matches(const CheckpointHeader& now, const std::string& path) const {
  for (const auto& [flag, value] : now.settings) {
    std::string saved = "(not recorded)";
    for (const auto& [f, v] : settings)
      if (f == flag) saved = v;
    if (saved != value)
      throw file_error(path, "checkpoint was made with " + flag + " " + saved + ", this run has " +
                                 value);
  }
  if (scene_fingerprint != now.scene_fingerprint)
    throw file_error(path,
                     "checkpoint was made from other scene files (the scene, or a mesh, texture "
                     "or spectrum it uses, has changed since)");
}

}  // namespace emlt::cli
