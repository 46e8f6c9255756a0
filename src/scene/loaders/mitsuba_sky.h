#pragma once
// Mitsuba 0.6's daylight emitters (`sky`, `sun`, `sunsky`) read into an environment map
// (internal to src/scene; the models are emlt/scene/sky.h).
#include <string>

#include "src/scene/loaders/mitsuba_parser.h"

namespace emlt::mitsuba {

bool is_sky_emitter(const std::string& type);

// Reads <emitter type="sky|sun|sunsky"> into `env` (a lat-long map with the emitter's
// toWorld), or leaves `env` untouched where emlt cannot render it (a `sun` made a
// directional light), saying so as an unsupported item.
void read_sky_emitter(const Document& doc, pugi::xml_node node, EnvironmentDesc& env);

}  // namespace emlt::mitsuba
