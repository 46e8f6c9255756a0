#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/fidelity.h"
#include "emlt/integrators/registry.h"
#include "emlt/run/scene_settings.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"

namespace emlt::cli {

namespace {

// `emlt info --json`: each warning with its kind, so that a tool can tell a note (emlt does
// as the file means) from an approximated or unsupported item without parsing sentences.
// A warning is a divergence of that kind when the loader recorded it as one (same text).
void print_json(const SceneDescription& d, const std::vector<std::string>& warnings) {
  std::vector<bool> matched(d.divergences.size(), false);
  nlohmann::json list = nlohmann::json::array();
  for (const std::string& warning : warnings) {
    std::string kind = "note";
    for (size_t i = 0; i < d.divergences.size(); ++i) {
      if (matched[i] || d.divergences[i].message != warning) continue;
      matched[i] = true;
      kind = d.divergences[i].kind == Divergence::Kind::Approximated ? "approximated"
                                                                     : "unsupported";
      break;
    }
    list.push_back({{"kind", kind}, {"message", warning}});
  }
  const nlohmann::json out = {{"scene", d.source}, {"warnings", list}, {"verdict", d.verdict()}};
  fmt::print("{}\n", out.dump(1));
}

}  // namespace

int run_info(const InfoOptions& options) {
  SceneDescription loaded = load_scene_description(options.scene, parse_defines(options.defines));
  refuse_divergences_if_strict(loaded, options.strict);
  const auto scene = Scene::build(std::move(loaded));
  const SceneStats& st = scene->stats();
  const SceneDescription& d = scene->description();
  if (options.json) {
    print_json(d, scene->warnings());
    return 0;
  }
  fmt::print("scene        {}\n", d.source);
  fmt::print("image        {}x{}\n", scene->camera().width(), scene->camera().height());
  fmt::print("triangles    {} ({} degenerate dropped) in {} meshes\n", st.triangles,
             st.dropped_degenerate_triangles, st.meshes);
  fmt::print("spheres      {}\n", st.spheres);
  fmt::print("rays         {}\n", st.direct_triangles
                                      ? "every triangle tested directly (a scene this small)"
                                      : "Embree's BVH");
  fmt::print("area lights  {} emissive triangles\n", st.area_lights);
  fmt::print("environment  {}\n", st.has_environment ? "yes" : "no");
  size_t spots = 0;
  for (const PointLightDesc& light : d.point_lights) spots += light.spot;
  if (!d.point_lights.empty() || !d.directional_lights.empty())
    fmt::print("delta lights {} point, {} spot, {} directional\n", d.point_lights.size() - spots,
               spots, d.directional_lights.size());
  fmt::print("materials    {}\n", d.materials.size());
  for (const auto& m : d.materials)
    fmt::print("  {:<20} {}\n", m.name, m.bsdf ? m.bsdf->name() : std::string("(none)"));
  RenderSettings s = settings_for(d.render);  // the file's, else the engine's defaults
  apply_integrator_options(d.render, s);
  fmt::print("integrator   {} (max depth {}, roulette after {} segments, {} spp{})\n", s.integrator,
             s.max_depth, s.rr_depth, s.spp, s.hide_emitters ? ", emitters hidden" : "");
  fmt::print("warnings     {}\n", scene->warnings().size());
  for (const auto& w : scene->warnings()) fmt::print("  {}\n", w);
  // Last, so that it is the line a user sees first: is this the scene the file means?
  fmt::print("verdict      {}\n", d.verdict());
  return 0;
}

}  // namespace emlt::cli
