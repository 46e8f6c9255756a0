#pragma once
// Scene files: native JSON (.json), Mitsuba 0.6 XML (.xml) and pbrt-v4 (.pbrt), chosen by
// extension. Each produces a SceneDescription (see scenes/README.md for the JSON format). Problems
// with the input throw emlt::Error "<file>: <problem>"; anything accepted but not reproduced
// exactly adds a line to SceneDescription::warnings.
#include <map>
#include <string>

#include "emlt/scene/description.h"

namespace emlt {

// Values for `$name` placeholders (command line `-D name=value`); they override the
// defaults a scene file declares.
using SceneDefines = std::map<std::string, std::string>;

SceneDescription load_scene_description(const std::string& path, const SceneDefines& defines = {});
SceneDescription load_json_scene(const std::string& path, const SceneDefines& defines = {});
SceneDescription load_mitsuba_scene(const std::string& path, const SceneDefines& defines = {});
// pbrt-v4's format has no placeholders: the defines are not used.
SceneDescription load_pbrt_scene(const std::string& path);

}  // namespace emlt
