#pragma once
// Mitsuba 0.6's <sensor> read into the scene's camera (internal to src/scene): the sensor
// itself, its <film> with the film's crop window, the film's reconstruction filter
// (<rfilter>) and its <sampler>.
#include "src/scene/loaders/mitsuba_parser.h"

namespace emlt::mitsuba {

// A `perspective`, `thinlens` or `orthographic` <sensor> into desc.camera, and what its
// <sampler> says about rendering into desc.render; any other sensor type is refused.
void read_sensor(const Document& doc, pugi::xml_node node, SceneDescription& desc);

}  // namespace emlt::mitsuba
