#include "support/loader_scenes.h"

#include "emlt/scene/scene.h"
#include "support/test_support.h"

namespace emlt::test {

std::string small_json(const std::string& camera_extra, const std::string& extra_shapes) {
  return R"({"camera": {"lookat": {"origin": [0,0,-5], "target": [0,0,0], "up": [0,1,0]}, "fov": 40)" +
         camera_extra + R"(},
  "shapes": [{"type": "rectangle", "emission": [1,1,1], "material": {"type": "diffuse"}})" +
         extra_shapes + "]}";
}

std::string small_xml(const std::string& body) {
  return R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film>
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter>
    <bsdf type="diffuse"/></shape>
)" + body +
         "\n</scene>\n";
}

bool any_contains(const std::vector<std::string>& lines, const std::string& needle) {
  for (const std::string& line : lines)
    if (line.find(needle) != std::string::npos) return true;
  return false;
}

std::string load_and_build_error(const std::string& path, const SceneDefines& defines) {
  return error_of([&] { Scene::build(load_scene_description(path, defines)); });
}

}  // namespace emlt::test
