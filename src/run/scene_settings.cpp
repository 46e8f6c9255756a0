#include "emlt/run/scene_settings.h"

namespace emlt {

RenderSettings settings_for(const SceneRenderRequest& request) {
  RenderSettings settings;
  if (!request.integrator.empty()) settings.integrator = request.integrator;
  if (request.spp) settings.spp = *request.spp;
  if (request.max_depth) settings.max_depth = *request.max_depth;
  if (request.rr_depth) settings.rr_depth = *request.rr_depth;
  if (request.hide_emitters) settings.hide_emitters = *request.hide_emitters;
  return settings;
}

}  // namespace emlt
