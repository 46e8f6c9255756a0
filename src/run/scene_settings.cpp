#include "emlt/run/scene_settings.h"

#include "emlt/settings/scene_options.h"

namespace emlt {

RenderSettings settings_for(const SceneRenderRequest& request) {
  RenderSettings settings;
  if (!request.integrator.empty()) settings.integrator = request.integrator;
  for (const auto& [flag, text] : request.options) scene_file_option(flag).option.set(settings, text);
  return settings;
}

}  // namespace emlt
