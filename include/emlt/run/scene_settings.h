#pragma once
// A render's settings before the command line has its say: the engine's defaults, then what
// the scene file says (its SceneRenderRequest).
#include "emlt/scene/description.h"
#include "emlt/settings/settings.h"

namespace emlt {

RenderSettings settings_for(const SceneRenderRequest& request);

}  // namespace emlt
