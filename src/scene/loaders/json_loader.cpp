// The native JSON scene format (documented with a complete example in scenes/README.md).
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>

#include "emlt/core/error.h"
#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/loaders/obj_loader.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/shape_builders.h"
#include "emlt/settings/scene_options.h"
#include "src/scene/loaders/json_scene_reader.h"
#include "src/scene/loaders/loader_common.h"
#include "src/scene/parameter_ranges.h"

namespace emlt {

namespace json_scene {

SceneDescription JsonSceneReader::read() {
  json root;
  try {
    root = json::parse(loader::read_text_file(path_));
  } catch (const json::exception& e) {  // parse_error, and out_of_range for 1e999
    fail("", std::string("malformed JSON: ") + e.what());
  }
  if (!root.is_object()) fail("", "the top level must be a JSON object");
  check_keys(root, "", {"camera", "integrator", "materials", "shapes", "environment", "defaults"});
  if (root.contains("defaults")) {
    if (!root["defaults"].is_object()) fail("defaults", "expected an object");
    for (const auto& [name, value] : root["defaults"].items()) file_defaults_[name] = value;
  }
  substitute(root, "");

  if (root.contains("camera")) read_camera(object(root["camera"], "camera"));
  if (root.contains("integrator")) read_integrator(object(root["integrator"], "integrator"));
  if (root.contains("materials")) {
    for (const auto& [name, spec] : object(root["materials"], "materials").items())
      named_materials_[name] = read_material(spec, "materials." + name);
  }
  if (root.contains("shapes")) {
    const json& shapes = root["shapes"];
    if (!shapes.is_array()) fail("shapes", "expected an array");
    for (size_t i = 0; i < shapes.size(); ++i)
      read_shape(object(shapes[i], "shapes[" + std::to_string(i) + "]"),
                 "shapes[" + std::to_string(i) + "]");
  }
  if (root.contains("environment")) read_environment(object(root["environment"], "environment"));
  return std::move(desc_);
}

void JsonSceneReader::check_keys(const json& obj, const std::string& where,
                                 std::initializer_list<const char*> allowed) {
  for (const auto& item : obj.items()) {
    bool known = false;
    for (const char* key : allowed) known |= item.key() == key;
    if (!known)
      warn("unknown key '" + item.key() + "'" + (where.empty() ? "" : " in " + where) + " ignored");
  }
}

void JsonSceneReader::substitute(json& value, const std::string& where) {
  if (value.is_string()) {
    const std::string& text = value.get_ref<const std::string&>();
    if (text.size() < 2 || text[0] != '$') return;
    const std::string name = text.substr(1);
    if (auto it = defines_.find(name); it != defines_.end()) {
      json parsed = json::parse(it->second, nullptr, false);
      value = parsed.is_discarded() ? json(it->second) : parsed;
    } else if (auto def = file_defaults_.find(name); def != file_defaults_.end()) {
      value = def->second;
    } else {
      fail(where, "parameter $" + name + " has no value (define it with -D " + name + "=...)");
    }
  } else if (value.is_object()) {
    for (auto& [key, child] : value.items())
      if (key != "defaults") substitute(child, where.empty() ? key : where + "." + key);
  } else if (value.is_array()) {
    for (size_t i = 0; i < value.size(); ++i)
      substitute(value[i], where + "[" + std::to_string(i) + "]");
  }
}

float JsonSceneReader::number(const json& v, const std::string& where) const {
  if (!v.is_number()) fail(where, "expected a number");
  // Checked after the conversion: 1e39 is a finite double but an infinite float.
  const auto x = float(v.get<double>());
  if (!std::isfinite(x))
    fail(where,
         "expected a finite number, not NaN or infinite (single precision reaches "
         "about +-3.4e38)");
  return x;
}

int JsonSceneReader::integer(const json& obj, const char* key, const std::string& where,
                             int fallback) const {
  if (!obj.contains(key)) return fallback;
  if (!obj[key].is_number_integer()) fail(where + "." + key, "expected an integer");
  // get<int> would wrap a larger one silently (10^12 pixels into a negative width).
  const bool fits = obj[key].is_number_unsigned() ? obj[key].get<uint64_t>() <= uint64_t(INT32_MAX)
                                                  : obj[key].get<int64_t>() >= INT32_MIN &&
                                                        obj[key].get<int64_t>() <= INT32_MAX;
  if (!fits) fail(where + "." + key, "expected an integer within +-2^31 (about 2.1 billion)");
  return int(obj[key].get<int64_t>());
}

Mat4 JsonSceneReader::transform(const json& list, const std::string& where) {
  if (!list.is_array()) fail(where, "expected an array of transform operations");
  Mat4 m(1.0f);
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string at = where + "[" + std::to_string(i) + "]";
    const json& op = object(list[i], at);
    if (op.size() != 1) fail(at, "each transform operation is an object with one key");
    const std::string kind = op.begin().key();
    const json& value = op.begin().value();
    Mat4 step(1.0f);
    if (kind == "translate") {
      step = glm::translate(Mat4(1.0f), vec3(value, at + ".translate"));
    } else if (kind == "scale") {
      step = glm::scale(Mat4(1.0f), value.is_number() ? Vec3(number(value, at + ".scale"))
                                                      : vec3(value, at + ".scale"));
    } else if (kind == "rotate") {
      check_keys(object(value, at + ".rotate"), at + ".rotate", {"axis", "angle"});
      step = loader::rotation_matrix(vec3(required(value, "axis", at), at + ".rotate.axis"),
                                     number(required(value, "angle", at), at + ".rotate.angle"));
    } else if (kind == "matrix") {
      step = matrix16(value, at + ".matrix");
    } else if (kind == "lookat") {
      step = look_at(value, at + ".lookat");
    } else {
      fail(at, "unknown transform operation '" + kind + "'");
    }
    m = step * m;
  }
  if (!is_finite_matrix(m)) fail(where, "transform contains NaN or infinite values");
  return m;
}

void JsonSceneReader::read_camera(const json& c) {
  check_keys(c, "camera",
             {"lookat", "matrix", "fov", "fov_axis", "aperture_radius", "focus_distance", "width",
              "height", "filter"});
  CameraDesc& camera = desc_.camera;
  if (c.contains("lookat") && c.contains("matrix"))
    fail("camera", "give either 'lookat' or 'matrix'");
  if (c.contains("lookat")) camera.to_world = look_at(c["lookat"], "camera.lookat");
  if (c.contains("matrix")) camera.to_world = matrix16(c["matrix"], "camera.matrix");
  camera.fov_degrees = number(c, "fov", "camera", camera.fov_degrees, loader::kFovRange);
  if (c.contains("fov_axis")) {
    const auto axis = parse_fov_axis(string(c["fov_axis"], "camera.fov_axis"));
    if (!axis) fail("camera.fov_axis", "expected \"x\", \"y\", \"smaller\" or \"larger\"");
    camera.fov_axis = *axis;
  }
  camera.aperture_radius =
      number(c, "aperture_radius", "camera", camera.aperture_radius, loader::kNonNegativeRange);
  camera.focus_distance =
      number(c, "focus_distance", "camera", camera.focus_distance, loader::kPositiveRange);
  camera.width = integer(c, "width", "camera", camera.width, loader::kFilmSideRange);
  camera.height = integer(c, "height", "camera", camera.height, loader::kFilmSideRange);
  if (c.contains("filter")) camera.filter = filter(c["filter"], "camera.filter");
}

PixelFilterDesc JsonSceneReader::filter(const json& f, const std::string& where) {
  check_keys(f, where, {"type", "stddev", "radius", "b", "c", "lobes"});
  PixelFilterDesc desc;
  const std::string type = f.contains("type") ? string(f["type"], where + ".type") : "box";
  if (type == "gaussian")
    desc.kind = PixelFilterDesc::Kind::Gaussian;
  else if (type == "tent")
    desc.kind = PixelFilterDesc::Kind::Tent;
  else if (type == "mitchell")
    desc.kind = PixelFilterDesc::Kind::Mitchell;
  else if (type == "catmullrom")
    desc.kind = PixelFilterDesc::Kind::CatmullRom;
  else if (type == "lanczos")
    desc.kind = PixelFilterDesc::Kind::Lanczos;
  else if (type != "box")
    fail(where + ".type",
         "unknown filter '" + type + "' (box, gaussian, tent, mitchell, catmullrom, lanczos)");
  desc.stddev = number(f, "stddev", where, desc.stddev, loader::kFilterStddevRange);
  desc.radius = number(f, "radius", where, desc.radius, loader::kFilterRadiusRange);
  desc.b = number(f, "b", where, desc.b);
  desc.c = number(f, "c", where, desc.c);
  desc.lobes = integer(f, "lobes", where, desc.lobes, loader::kFilterLobesRange);
  return desc;
}

void JsonSceneReader::read_integrator(const json& i) {
  // Beside its type, the integrator object takes the options a scene file shares with the
  // command line (settings/scene_options.h), each under its flag's name ("max_depth").
  for (const auto& item : i.items()) {
    bool known = item.key() == "type";
    for (const SceneFileOption& o : scene_file_options()) known |= item.key() == o.json_key();
    if (!known) warn("unknown key '" + item.key() + "' in integrator ignored");
  }
  SceneRenderRequest& r = desc_.render;
  if (i.contains("type")) r.integrator = string(i["type"], "integrator.type");
  for (const SceneFileOption& o : scene_file_options()) {
    const std::string key = o.json_key();
    if (!i.contains(key)) continue;
    r.set(o.option.flag, o.boolean()
                             ? o.word(boolean(i, key.c_str(), "integrator", false))
                             : std::to_string(integer(i, key.c_str(), "integrator", 0,
                                                      loader::whole_range(o.option.values))));
  }
}

int JsonSceneReader::material_for_shape(const json& s, const std::string& where) {
  if (!s.contains("material")) return -1;
  const json& m = s["material"];
  if (m.is_string()) {
    const std::string name = m.get<std::string>();
    auto it = named_materials_.find(name);
    if (it == named_materials_.end()) fail(where + ".material", "unknown material '" + name + "'");
    MaterialDesc material = it->second;
    material.name = name;
    return loader::material_index(desc_, material);
  }
  MaterialDesc material = read_material(m, where + ".material");
  material.name = where;
  return loader::material_index(desc_, material);
}

void JsonSceneReader::read_shape(const json& s, const std::string& where) {
  const std::string type = string(required(s, "type", where), where + ".type");
  const std::string name =
      s.contains("name") ? string(s["name"], where + ".name") : where + " (" + type + ")";
  const Mat4 to_world =
      s.contains("transform") ? transform(s["transform"], where + ".transform") : Mat4(1.0f);
  const int material = material_for_shape(s, where);
  const Rgb emission = color(s, "emission", where, Rgb(0.0f));
  const bool flip = boolean(s, "flip_normals", where, false);

  if (type == "sphere") {
    check_keys(
        s, where,
        {"type", "name", "transform", "material", "emission", "flip_normals", "center", "radius"});
    SphereDesc sphere;
    sphere.name = name;
    sphere.center = s.contains("center") ? vec3(s["center"], where + ".center") : Vec3(0.0f);
    sphere.radius = number(s, "radius", where, 1.0f, loader::kPositiveRange);
    loader::transform_sphere(sphere, to_world, path_ + ": " + where, desc_.warnings);
    sphere.material = material;
    sphere.emission = emission;
    sphere.flip_normals = flip;
    desc_.spheres.push_back(sphere);
    return;
  }
  MeshDesc mesh;
  if (type == "obj") {
    check_keys(s, where,
               {"type", "name", "transform", "material", "emission", "flip_normals", "file",
                "smooth_normals", "flip_tex_coords"});
    const std::string file =
        loader::resolve_path(path_, string(required(s, "file", where), where + ".file"));
    mesh = load_obj_mesh(file, to_world, boolean(s, "smooth_normals", where, false),
                         &desc_.warnings, boolean(s, "flip_tex_coords", where, true));
    loader::drop_non_finite_triangles(desc_, mesh, file);
  } else {
    check_keys(s, where, {"type", "name", "transform", "material", "emission", "flip_normals"});
    if (type == "rectangle")
      mesh = make_rectangle_mesh(to_world);
    else if (type == "cube")
      mesh = make_cube_mesh(to_world);
    else if (type == "disk")
      mesh = make_disk_mesh(to_world);
    else
      fail(where + ".type",
           "unknown shape type '" + type + "' (obj, rectangle, cube, disk, sphere)");
  }
  if (flip) flip_mesh_normals(mesh);
  if (s.contains("name") || type != "obj") mesh.name = name;
  mesh.material = material;
  mesh.emission = emission;
  desc_.meshes.push_back(std::move(mesh));
}

void JsonSceneReader::read_environment(const json& e) {
  const std::string type = string(required(e, "type", "environment"), "environment.type");
  EnvironmentDesc& env = desc_.environment;
  if (type == "constant") {
    check_keys(e, "environment", {"type", "radiance"});
    env.kind = EnvironmentDesc::Kind::Constant;
    env.radiance = color(e, "radiance", "environment", Rgb(1.0f));
  } else if (type == "envmap") {
    check_keys(e, "environment", {"type", "file", "scale", "transform"});
    env.scale = number(e, "scale", "environment", 1.0f, loader::kNonNegativeRange);
    if (e.contains("transform")) env.to_world = transform(e["transform"], "environment.transform");
    loader::load_environment_map(
        env, path_,
        loader::resolve_path(path_,
                             string(required(e, "file", "environment"), "environment.file")));
  } else if (type == "cubemap") {
    check_keys(e, "environment", {"type", "faces", "scale", "transform"});
    env.scale = number(e, "scale", "environment", 1.0f, loader::kNonNegativeRange);
    if (e.contains("transform")) env.to_world = transform(e["transform"], "environment.transform");
    const json& faces = required(e, "faces", "environment");
    if (!faces.is_array() || faces.size() != 6)
      fail("environment.faces", "expected six file names (+x, -x, +y, -y, +z, -z)");
    std::vector<std::string> files;
    for (size_t f = 0; f < faces.size(); ++f)
      files.push_back(loader::resolve_path(
          path_, string(faces[f], "environment.faces[" + std::to_string(f) + "]")));
    loader::load_cube_map(env, path_, files);
  } else {
    fail("environment.type", "unknown environment type '" + type + "' (constant, envmap, cubemap)");
  }
}

}  // namespace json_scene

SceneDescription load_json_scene(const std::string& path, const SceneDefines& defines) {
  return json_scene::JsonSceneReader(path, defines).read();
}

}  // namespace emlt
