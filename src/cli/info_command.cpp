#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/fidelity.h"
#include "emlt/run/scene_settings.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"

namespace emlt::cli {

int run_info(const InfoOptions& options) {
  SceneDescription loaded = load_scene_description(options.scene, parse_defines(options.defines));
  refuse_divergences_if_strict(loaded, options.strict);
  const auto scene = Scene::build(std::move(loaded));
  const SceneStats& st = scene->stats();
  const SceneDescription& d = scene->description();
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
  const RenderSettings s = settings_for(d.render);  // the file's, else the engine's defaults
  fmt::print("integrator   {} (max depth {}, roulette after {} segments, {} spp{})\n", s.integrator,
             s.max_depth, s.rr_depth, s.spp, s.hide_emitters ? ", emitters hidden" : "");
  fmt::print("warnings     {}\n", scene->warnings().size());
  for (const auto& w : scene->warnings()) fmt::print("  {}\n", w);
  // Last, so that it is the line a user sees first: is this the scene the file means?
  fmt::print("verdict      {}\n", d.verdict());
  return 0;
}

}  // namespace emlt::cli
