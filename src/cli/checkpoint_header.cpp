#include "cli/checkpoint_header.h"

#include <fmt/core.h>

#include <fstream>
#include <iterator>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/state_io.h"
#include "emlt/integrators/registry.h"
#include "emlt/settings/render_option.h"

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
  // Every declared option whose value is part of what the render is and that this render's
  // integrator reads (render_option.h).
  for (const RenderOption& option : render_options())
    if (option.recorded && (!option.applies || option.applies(s)))
      add(option.flag.c_str(), option.recorded(s));
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
    bool recorded = false;
    for (const auto& [f, v] : settings)
      if (f == flag) saved = v, recorded = true;
    // An option a checkpoint does not record was declared after it was written, by a
    // version whose renders all had the option's default: such a checkpoint resumes when
    // this run keeps the default.
    if (!recorded)
      for (const RenderOption& option : render_options())
        if (option.flag == flag && option.recorded && option.recorded(RenderSettings()) == value)
          saved = value;
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
