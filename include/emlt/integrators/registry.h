#pragma once
// Every integrator by the name the command line and the scene files give it: one line each
// in src/integrators/registry.cpp, which sits above all of them.
#include <memory>
#include <string>
#include <vector>

#include "emlt/run/integrator.h"
#include "emlt/scene/description.h"
#include "emlt/settings/render_option.h"

namespace emlt {

// The integrator called `name`; throws Error naming the known ones when there is none.
std::unique_ptr<Integrator> make_integrator(const std::string& name);
// The names, in the order the command line lists them.
std::vector<std::string> integrator_names();
// Every option the integrators and the run loop declare (render_option.h), each flag once,
// in the order the command line lists them.
const std::vector<RenderOption>& render_options();
// A scene file's options of its integrator's own (SceneRenderRequest::integrator_options),
// set through their flags; a flag no integrator declares is an Error naming it.
void apply_integrator_options(const SceneRenderRequest& request, RenderSettings& settings);

}  // namespace emlt
