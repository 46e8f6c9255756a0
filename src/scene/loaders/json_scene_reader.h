#pragma once
// The JSON scene reader (internal to src/scene/loaders): the typed access to a file's values
// that every part shares, and the readers of its parts, defined in json_loader.cpp (the file,
// camera, integrator, shapes, environment) and json_materials.cpp (materials and textures).
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "emlt/core/error.h"
#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/texture.h"
#include "src/scene/parameter_ranges.h"

namespace emlt::json_scene {

using nlohmann::json;

class JsonSceneReader {
 public:
  JsonSceneReader(std::string path, const SceneDefines& defines)
      : path_(std::move(path)), defines_(defines) {
    desc_.source = path_;
  }

  SceneDescription read();

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
    throw file_error(path_, where.empty() ? problem : where + ": " + problem);
  }

  void warn(const std::string& message) { desc_.warnings.push_back(path_ + ": " + message); }

  void check_keys(const json& obj, const std::string& where,
                  std::initializer_list<const char*> allowed);

  // Replaces every string "$name" by the define (parsed as JSON when it is valid JSON, so
  // -D spp=64 gives a number) or the file's "defaults" entry.
  void substitute(json& value, const std::string& where);

  const json& object(const json& v, const std::string& where) const {
    if (!v.is_object()) fail(where, "expected an object");
    return v;
  }

  const json& required(const json& obj, const char* key, const std::string& where) const {
    if (!obj.contains(key)) fail(where, std::string("missing required key '") + key + "'");
    return obj[key];
  }

  float number(const json& v, const std::string& where) const;

  float number(const json& obj, const char* key, const std::string& where, float fallback) const {
    return obj.contains(key) ? number(obj[key], where + "." + key) : fallback;
  }

  // A number refused outside `range`, in words: "camera.fov: must be a number of degrees
  // between 0 and 180, both excluded (got 180)".
  float number(const json& v, const std::string& where, const loader::RealRange& range) const {
    const float x = number(v, where);
    if (!range.contains(x)) fail(where, loader::refusal(range.words, v.dump()));
    return x;
  }

  float number(const json& obj, const char* key, const std::string& where, float fallback,
               const loader::RealRange& range) const {
    return obj.contains(key) ? number(obj[key], where + "." + key, range) : fallback;
  }

  int integer(const json& obj, const char* key, const std::string& where, int fallback) const;

  // An integer refused outside `range`, in the command line's words for the same setting.
  int integer(const json& obj, const char* key, const std::string& where, int fallback,
              const loader::IntegerRange& range) const {
    const int value = integer(obj, key, where, fallback);
    if (obj.contains(key) && !range.contains(value))
      fail(where + "." + key, loader::refusal(range.words, obj[key].dump()));
    return value;
  }

  bool boolean(const json& obj, const char* key, const std::string& where, bool fallback) const {
    if (!obj.contains(key)) return fallback;
    if (!obj[key].is_boolean()) fail(where + "." + key, "expected true or false");
    return obj[key].get<bool>();
  }

  std::string string(const json& v, const std::string& where) const {
    if (!v.is_string()) fail(where, "expected a string");
    return v.get<std::string>();
  }

  Vec3 vec3(const json& v, const std::string& where) const {
    if (!v.is_array() || v.size() != 3) fail(where, "expected an array of 3 numbers");
    return Vec3(number(v[0], where), number(v[1], where), number(v[2], where));
  }

  // A colour is [r, g, b] or one number for grey.
  Rgb color(const json& obj, const char* key, const std::string& where, Rgb fallback) const {
    if (!obj.contains(key)) return fallback;
    const json& v = obj[key];
    if (v.is_number()) return Rgb(number(v, where + "." + key));
    return vec3(v, where + "." + key);
  }

  // A colour, or a texture object wherever a colour is accepted:
  //   {"type": "bitmap", "file": "wood.png", "raw": false, "wrap": "repeat", <uv>}
  //   {"type": "checkerboard", "color0": c, "color1": c, <uv>}
  //   {"type": "scale", "scale": c, "texture": {...}}
  // with <uv> = "uvscale", "uscale", "vscale", "uoffset", "voffset" (Mitsuba's). Counts the
  // textures that vary over the surface in varying_textures_.
  TexturePtr texture(const json& obj, const char* key, const std::string& where, Rgb fallback);

  TexturePtr texture_object(const json& t, const std::string& where);

  // A roughness: a number or a texture (its channel mean is used).
  TexturePtr roughness(const json& m, const std::string& where, float fallback);

  MicrofacetType distribution(const json& m, const std::string& where) const;

  float ior(const json& obj, const char* key, const std::string& where, float fallback) const;

  Mat4 matrix16(const json& v, const std::string& where) const {
    if (!v.is_array() || v.size() != 16) fail(where, "expected an array of 16 numbers (row-major)");
    Mat4 m(1.0f);
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 4; ++col) m[col][row] = number(v[size_t(row * 4 + col)], where);
    return m;
  }

  Mat4 look_at(const json& v, const std::string& where) {
    check_keys(object(v, where), where, {"origin", "target", "up"});
    return look_at_matrix(vec3(required(v, "origin", where), where + ".origin"),
                          vec3(required(v, "target", where), where + ".target"),
                          v.contains("up") ? vec3(v["up"], where + ".up") : Vec3(0, 1, 0));
  }

  // A list of operations applied in order (the first listed acts first).
  Mat4 transform(const json& list, const std::string& where);

  void read_camera(const json& c);

  // {"type": "box"} (the default), {"type": "gaussian", "stddev": 0.5} (Mitsuba's film
  // default), {"type": "tent", "radius": 1}.
  PixelFilterDesc filter(const json& f, const std::string& where);

  void read_integrator(const json& i);

  void conductor_ior(const json& m, const std::string& where, Rgb* eta, Rgb* k) const;

  MaterialDesc read_material(const json& spec, const std::string& where);

  int material_for_shape(const json& s, const std::string& where);

  void read_shape(const json& s, const std::string& where);

  void read_environment(const json& e);

  std::string path_;
  const SceneDefines& defines_;
  std::map<std::string, json> file_defaults_;
  std::map<std::string, MaterialDesc> named_materials_;
  int varying_textures_ = 0;
  SceneDescription desc_;
};

}  // namespace emlt::json_scene
