#pragma once
// Mitsuba 0.6's daylight emitters (`sky`, `sun`, `sunsky`) read into an environment map
// (internal to src/scene; the models are emlt/scene/sky.h).
#include <string>

#include "src/scene/loaders/mitsuba_parser.h"

namespace emlt::mitsuba {

bool is_sky_emitter(const std::string& type);

// Reads <emitter type="sky|sun|sunsky"> into the scene's environment (a lat-long map with
// the emitter's toWorld) and, where sunRadiusScale is 0, its sun into a directional light,
// as Mitsuba does (the sun's radiance times the solid angle of its disk).
void read_sky_emitter(const Document& doc, pugi::xml_node node, SceneDescription& desc);

}  // namespace emlt::mitsuba
