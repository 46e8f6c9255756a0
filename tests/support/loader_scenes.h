#pragma once
// What the loader tests share: a minimal scene in either format (a camera looking at one
// emissive rectangle) that a test adds to, and the checks on what loading a file says.
#include <string>
#include <vector>

#include "emlt/scene/loaders/loader.h"

namespace emlt::test {

// A JSON scene with one emissive rectangle and whatever `extra_shapes` adds; `camera_extra`
// is added to the camera's keys.
std::string small_json(const std::string& camera_extra, const std::string& extra_shapes);
// A Mitsuba scene: a 16x16 perspective sensor with a box filter, one emissive rectangle, and
// `body` after them (its text begins on line 10 of the file).
std::string small_xml(const std::string& body);
// Whether any of `lines` (a description's warnings) contains `needle`.
bool any_contains(const std::vector<std::string>& lines, const std::string& needle);
// The message of the error that loading `path` and building its scene gives ("" when none).
std::string load_and_build_error(const std::string& path, const SceneDefines& defines = {});

}  // namespace emlt::test
