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
#include "src/scene/loaders/loader_common.h"
#include "src/scene/parameter_ranges.h"

namespace emlt {

namespace {

using nlohmann::json;

class JsonSceneReader {
 public:
  JsonSceneReader(std::string path, const SceneDefines& defines)
      : path_(std::move(path)), defines_(defines) {
    desc_.source = path_;
  }

  SceneDescription read() {
    json root;
    try {
      root = json::parse(loader::read_text_file(path_));
    } catch (const json::exception& e) {  // parse_error, and out_of_range for 1e999
      fail("", std::string("malformed JSON: ") + e.what());
    }
    if (!root.is_object()) fail("", "the top level must be a JSON object");
    check_keys(root, "",
               {"camera", "integrator", "materials", "shapes", "environment", "defaults"});
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

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
    throw file_error(path_, where.empty() ? problem : where + ": " + problem);
  }

  void warn(const std::string& message) { desc_.warnings.push_back(path_ + ": " + message); }

  void check_keys(const json& obj, const std::string& where,
                  std::initializer_list<const char*> allowed) {
    for (const auto& item : obj.items()) {
      bool known = false;
      for (const char* key : allowed) known |= item.key() == key;
      if (!known)
        warn("unknown key '" + item.key() + "'" + (where.empty() ? "" : " in " + where) +
             " ignored");
    }
  }

  // Replaces every string "$name" by the define (parsed as JSON when it is valid JSON, so
  // -D spp=64 gives a number) or the file's "defaults" entry.
  void substitute(json& value, const std::string& where) {
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

  const json& object(const json& v, const std::string& where) const {
    if (!v.is_object()) fail(where, "expected an object");
    return v;
  }

  const json& required(const json& obj, const char* key, const std::string& where) const {
    if (!obj.contains(key)) fail(where, std::string("missing required key '") + key + "'");
    return obj[key];
  }

  float number(const json& v, const std::string& where) const {
    if (!v.is_number()) fail(where, "expected a number");
    // Checked after the conversion: 1e39 is a finite double but an infinite float.
    const auto x = float(v.get<double>());
    if (!std::isfinite(x))
      fail(where,
           "expected a finite number, not NaN or infinite (single precision reaches "
           "about +-3.4e38)");
    return x;
  }

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

  int integer(const json& obj, const char* key, const std::string& where, int fallback) const {
    if (!obj.contains(key)) return fallback;
    if (!obj[key].is_number_integer()) fail(where + "." + key, "expected an integer");
    // get<int> would wrap a larger one silently (10^12 pixels into a negative width).
    const bool fits =
        obj[key].is_number_unsigned()
            ? obj[key].get<uint64_t>() <= uint64_t(INT32_MAX)
            : obj[key].get<int64_t>() >= INT32_MIN && obj[key].get<int64_t>() <= INT32_MAX;
    if (!fits) fail(where + "." + key, "expected an integer within +-2^31 (about 2.1 billion)");
    return int(obj[key].get<int64_t>());
  }

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
  TexturePtr texture(const json& obj, const char* key, const std::string& where, Rgb fallback) {
    if (!obj.contains(key)) return make_constant_texture(fallback);
    const json& v = obj[key];
    if (!v.is_object()) return make_constant_texture(color(obj, key, where, fallback));
    TexturePtr t = texture_object(v, where + "." + key);
    if (!t->constant()) ++varying_textures_;
    return t;
  }

  TexturePtr texture_object(const json& t, const std::string& where) {
    const std::string type = string(required(t, "type", where), where + ".type");
    auto uv = [&] {
      const float uniform = number(t, "uvscale", where, 1.0f);
      UvTransform transform;
      transform.scale =
          Vec2(number(t, "uscale", where, uniform), number(t, "vscale", where, uniform));
      transform.offset = Vec2(number(t, "uoffset", where, 0.0f), number(t, "voffset", where, 0.0f));
      return transform;
    };
    if (type == "bitmap") {
      check_keys(
          t, where,
          {"type", "file", "raw", "wrap", "uvscale", "uscale", "vscale", "uoffset", "voffset"});
      const std::string file =
          loader::resolve_path(path_, string(required(t, "file", where), where + ".file"));
      std::error_code ec;
      if (!std::filesystem::is_regular_file(file, ec))
        fail(where + ".file", "texture image '" + file + "' not found");
      WrapMode wrap = WrapMode::Repeat;
      if (t.contains("wrap")) {
        const std::string mode = string(t["wrap"], where + ".wrap");
        if (mode == "mirror")
          wrap = WrapMode::Mirror;
        else if (mode == "clamp")
          wrap = WrapMode::Clamp;
        else if (mode == "zero")
          wrap = WrapMode::Zero;
        else if (mode == "one")
          wrap = WrapMode::One;
        else if (mode != "repeat")
          fail(where + ".wrap", "expected \"repeat\", \"mirror\", \"clamp\", \"zero\" or \"one\"");
      }
      // "raw": the stored values read linearly (gamma 1), whatever the file's curve.
      const bool raw = boolean(t, "raw", where, false);
      return load_bitmap_texture(file, raw ? std::optional<float>(1.0f) : std::nullopt, uv(), wrap);
    }
    if (type == "checkerboard") {
      check_keys(t, where,
                 {"type", "color0", "color1", "uvscale", "uscale", "vscale", "uoffset", "voffset"});
      return make_checkerboard_texture(color(t, "color0", where, Rgb(0.4f)),
                                       color(t, "color1", where, Rgb(0.2f)), uv());
    }
    if (type == "scale") {
      check_keys(t, where, {"type", "scale", "texture"});
      const json& inner = required(t, "texture", where);
      TexturePtr nested = inner.is_object()
                              ? texture_object(inner, where + ".texture")
                              : make_constant_texture(color(t, "texture", where, Rgb(1.0f)));
      return make_scale_texture(nested, color(t, "scale", where, Rgb(1.0f)));
    }
    fail(where + ".type", "unknown texture type '" + type + "' (bitmap, checkerboard, scale)");
  }

  // A roughness: a number or a texture (its channel mean is used).
  TexturePtr roughness(const json& m, const std::string& where, float fallback) {
    TexturePtr alpha = texture(m, "alpha", where, Rgb(fallback));
    if (auto c = alpha->constant(); c && !(c->x >= 0.0f)) fail(where + ".alpha", "must be >= 0");
    return alpha;
  }

  MicrofacetType distribution(const json& m, const std::string& where) const {
    const std::string name =
        m.contains("distribution") ? string(m["distribution"], where + ".distribution") : "ggx";
    if (name == "ggx") return MicrofacetType::Ggx;
    if (name == "beckmann") return MicrofacetType::Beckmann;
    if (name == "phong") return MicrofacetType::Phong;
    fail(where + ".distribution", "expected \"ggx\", \"beckmann\" or \"phong\"");
  }

  float ior(const json& obj, const char* key, const std::string& where, float fallback) const {
    if (!obj.contains(key)) return fallback;
    if (obj[key].is_string()) {
      const std::string name = obj[key].get<std::string>();
      if (auto value = loader::named_ior(name)) return *value;
      fail(where + "." + key, "unknown index of refraction name '" + name + "'");
    }
    return number(obj[key], where + "." + key, loader::kPositiveRange);
  }

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
  Mat4 transform(const json& list, const std::string& where) {
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

  void read_camera(const json& c) {
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

  // {"type": "box"} (the default), {"type": "gaussian", "stddev": 0.5} (Mitsuba's film
  // default), {"type": "tent", "radius": 1}.
  PixelFilterDesc filter(const json& f, const std::string& where) {
    check_keys(f, where, {"type", "stddev", "radius"});
    PixelFilterDesc desc;
    const std::string type = f.contains("type") ? string(f["type"], where + ".type") : "box";
    if (type == "gaussian")
      desc.kind = PixelFilterDesc::Kind::Gaussian;
    else if (type == "tent")
      desc.kind = PixelFilterDesc::Kind::Tent;
    else if (type != "box")
      fail(where + ".type", "unknown filter '" + type + "' (box, gaussian, tent)");
    desc.stddev = number(f, "stddev", where, desc.stddev, loader::kFilterStddevRange);
    desc.radius = number(f, "radius", where, desc.radius, loader::kFilterRadiusRange);
    return desc;
  }

  void read_integrator(const json& i) {
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
      r.set(o.option.flag,
            o.boolean() ? o.word(boolean(i, key.c_str(), "integrator", false))
                        : std::to_string(integer(i, key.c_str(), "integrator", 0,
                                                 loader::whole_range(o.option.values))));
    }
  }

  void conductor_ior(const json& m, const std::string& where, Rgb* eta, Rgb* k) const {
    const bool explicit_ior = m.contains("eta") || m.contains("k");
    if (explicit_ior && m.contains("material")) fail(where, "give either 'material' or 'eta'/'k'");
    if (explicit_ior) {
      *eta = color(m, "eta", where, Rgb(0.0f));
      *k = color(m, "k", where, Rgb(1.0f));
    } else {
      const std::string name =
          m.contains("material") ? string(m["material"], where + ".material") : "Cu";
      if (!conductor_preset(name, eta, k))
        fail(where + ".material", "unknown conductor '" + name + "'");
    }
    // As Mitsuba's conductors (extEta "air"): relative to air, and only eta^2, k^2 matter.
    *eta = glm::abs(*eta / 1.000277f);
    *k = glm::abs(*k / 1.000277f);
  }

  MaterialDesc read_material(const json& spec, const std::string& where) {
    const json& m = object(spec, where);
    const std::string type = string(required(m, "type", where), where + ".type");
    const int textures_before = varying_textures_;
    BsdfPtr bsdf;
    bool opaque = true;
    if (type == "diffuse") {
      check_keys(m, where, {"type", "reflectance", "two_sided", "opacity", "bump"});
      bsdf = make_lambertian(texture(m, "reflectance", where, Rgb(0.5f)));
    } else if (type == "roughdiffuse") {
      check_keys(
          m, where,
          {"type", "reflectance", "alpha", "use_fast_approx", "two_sided", "opacity", "bump"});
      bsdf =
          make_rough_diffuse(texture(m, "reflectance", where, Rgb(0.5f)), roughness(m, where, 0.2f),
                             boolean(m, "use_fast_approx", where, false));
    } else if (type == "phong") {
      check_keys(m, where,
                 {"type", "exponent", "specular_reflectance", "diffuse_reflectance", "two_sided",
                  "opacity", "bump"});
      TexturePtr exponent = texture(m, "exponent", where, Rgb(30.0f));
      if (auto c = exponent->constant(); c && !(c->x >= 0.0f))
        fail(where + ".exponent", "must be >= 0");
      bsdf = make_phong(exponent, texture(m, "specular_reflectance", where, Rgb(0.2f)),
                        texture(m, "diffuse_reflectance", where, Rgb(0.5f)));
    } else if (type == "ward") {
      check_keys(m, where,
                 {"type", "variant", "alpha", "alpha_u", "alpha_v", "specular_reflectance",
                  "diffuse_reflectance", "two_sided", "opacity", "bump"});
      const std::string name =
          m.contains("variant") ? string(m["variant"], where + ".variant") : "balanced";
      WardVariant variant = WardVariant::Balanced;
      if (name == "ward")
        variant = WardVariant::Ward;
      else if (name == "ward-duer")
        variant = WardVariant::WardDuer;
      else if (name != "balanced")
        fail(where + ".variant", "expected \"ward\", \"ward-duer\" or \"balanced\"");
      const float alpha =
          m.contains("alpha") ? number(m["alpha"], where + ".alpha", loader::kPositiveRange) : 0.1f;
      TexturePtr alpha_u = texture(m, "alpha_u", where, Rgb(alpha));
      TexturePtr alpha_v = texture(m, "alpha_v", where, Rgb(alpha));
      for (const auto& [key, a] : {std::pair{"alpha_u", alpha_u}, std::pair{"alpha_v", alpha_v}})
        if (auto c = a->constant(); c && !(c->x > 0.0f)) fail(where + "." + key, "must be > 0");
      bsdf =
          make_ward(variant, alpha_u, alpha_v, texture(m, "specular_reflectance", where, Rgb(0.2f)),
                    texture(m, "diffuse_reflectance", where, Rgb(0.5f)));
    } else if (type == "difftrans") {
      check_keys(m, where, {"type", "transmittance", "opacity", "bump"});
      opaque = false;
      bsdf = make_diffuse_transmitter(texture(m, "transmittance", where, Rgb(0.5f)));
    } else if (type == "mirror") {
      check_keys(m, where, {"type", "reflectance", "two_sided", "opacity", "bump"});
      bsdf = make_mirror(color(m, "reflectance", where, Rgb(1.0f)));
    } else if (type == "dielectric" || type == "thindielectric" || type == "roughdielectric") {
      check_keys(m, where,
                 {"type", "int_ior", "ext_ior", "specular_reflectance", "specular_transmittance",
                  "alpha", "distribution", "opacity", "bump"});
      opaque = false;
      const float int_ior = ior(m, "int_ior", where, 1.5046f);
      const float ext_ior = ior(m, "ext_ior", where, 1.000277f);
      const Rgb reflectance = color(m, "specular_reflectance", where, Rgb(1.0f));
      const Rgb transmittance = color(m, "specular_transmittance", where, Rgb(1.0f));
      if (type != "roughdielectric" && (m.contains("alpha") || m.contains("distribution")))
        warn(where + ": 'alpha'/'distribution' ignored on a smooth " + type);
      if (type == "dielectric")
        bsdf = make_dielectric(int_ior, ext_ior, reflectance, transmittance);
      else if (type == "thindielectric")
        bsdf = make_thin_dielectric(int_ior, ext_ior, reflectance, transmittance);
      else
        bsdf = make_rough_dielectric(roughness(m, where, 0.1f), int_ior, ext_ior,
                                     distribution(m, where), reflectance, transmittance);
    } else if (type == "conductor" || type == "roughconductor") {
      check_keys(m, where,
                 {"type", "alpha", "distribution", "material", "eta", "k", "specular_reflectance",
                  "two_sided", "opacity", "bump"});
      Rgb eta, k;
      conductor_ior(m, where, &eta, &k);
      TexturePtr specular = texture(m, "specular_reflectance", where, Rgb(1.0f));
      if (type == "conductor" && (m.contains("alpha") || m.contains("distribution")))
        warn(where + ": 'alpha'/'distribution' ignored on a smooth conductor");
      bsdf = type == "conductor" ? make_conductor(eta, k, specular)
                                 : make_rough_conductor(roughness(m, where, 0.1f), eta, k, specular,
                                                        distribution(m, where));
    } else if (type == "plastic" || type == "roughplastic") {
      check_keys(m, where,
                 {"type", "alpha", "distribution", "diffuse_reflectance", "specular_reflectance",
                  "int_ior", "ext_ior", "nonlinear", "two_sided", "opacity", "bump"});
      if (type == "plastic" && (m.contains("alpha") || m.contains("distribution")))
        warn(where + ": 'alpha'/'distribution' ignored on smooth plastic");
      TexturePtr alpha =
          type == "plastic" ? make_constant_texture(Rgb(0.0f)) : roughness(m, where, 0.1f);
      bsdf = make_rough_plastic(
          alpha, texture(m, "diffuse_reflectance", where, Rgb(0.5f)),
          texture(m, "specular_reflectance", where, Rgb(1.0f)), ior(m, "int_ior", where, 1.49f),
          ior(m, "ext_ior", where, 1.000277f), boolean(m, "nonlinear", where, false),
          type == "plastic" ? MicrofacetType::Ggx : distribution(m, where));
    } else if (type == "mixture" || type == "blend") {
      // Weighted sums of nested materials (Mitsuba's mixturebsdf and blendbsdf); each part
      // keeps its own sidedness, and opacity and bump belong to the whole surface.
      const bool mixture = type == "mixture";
      if (mixture)
        check_keys(
            m, where,
            {"type", "materials", "weights", "ensure_energy_conservation", "opacity", "bump"});
      else
        check_keys(m, where, {"type", "materials", "weight", "opacity", "bump"});
      opaque = false;
      const json& list = required(m, "materials", where);
      if (!list.is_array()) fail(where + ".materials", "expected an array of materials");
      std::vector<BsdfPtr> parts;
      for (size_t i = 0; i < list.size(); ++i) {
        const std::string at = where + ".materials[" + std::to_string(i) + "]";
        const MaterialDesc part = read_material(list[i], at);
        if (part.opacity || part.bump)
          fail(at, "a part of a " + type + " takes no opacity or bump");
        parts.push_back(part.bsdf);
      }
      if (mixture) {
        const json& weights = required(m, "weights", where);
        if (!weights.is_array() || weights.size() != parts.size())
          fail(where + ".weights", "expected one number per material");
        std::vector<float> values;
        float total = 0.0f;
        for (size_t i = 0; i < weights.size(); ++i) {
          values.push_back(number(weights[i], where + ".weights[" + std::to_string(i) + "]",
                                  loader::kNonNegativeRange));
          total += values.back();
        }
        if (!(total > 0.0f)) fail(where + ".weights", "must sum to more than 0");
        bsdf = make_mixture(parts, values, boolean(m, "ensure_energy_conservation", where, true));
      } else {
        if (parts.size() != 2) fail(where + ".materials", "a blend takes exactly two materials");
        bsdf = make_blend(texture(m, "weight", where, Rgb(0.5f)), parts[0], parts[1]);
      }
    } else {
      fail(where + ".type",
           "unknown material type '" + type +
               "' (diffuse, roughdiffuse, phong, ward, difftrans, mirror, dielectric, "
               "roughdielectric, thindielectric, conductor, roughconductor, plastic, "
               "roughplastic, mixture, blend)");
    }
    // Opaque surfaces are two-sided by default: a single-sided wall seen from behind
    // renders black, which is rarely what a hand-written scene means.
    if (opaque && boolean(m, "two_sided", where, true)) bsdf = make_two_sided(bsdf);
    MaterialDesc material("", bsdf);
    // Surface modifiers (Mitsuba's mask and bumpmap): "opacity" in [0, 1] and "bump", a
    // height texture in world units per unit uv.
    if (m.contains("opacity")) material.opacity = texture(m, "opacity", where, Rgb(1.0f));
    if (m.contains("bump")) material.bump = texture(m, "bump", where, Rgb(0.0f));
    material.textured = varying_textures_ > textures_before || material.bump;
    return material;
  }

  int material_for_shape(const json& s, const std::string& where) {
    if (!s.contains("material")) return -1;
    const json& m = s["material"];
    if (m.is_string()) {
      const std::string name = m.get<std::string>();
      auto it = named_materials_.find(name);
      if (it == named_materials_.end())
        fail(where + ".material", "unknown material '" + name + "'");
      MaterialDesc material = it->second;
      material.name = name;
      return loader::material_index(desc_, material);
    }
    MaterialDesc material = read_material(m, where + ".material");
    material.name = where;
    return loader::material_index(desc_, material);
  }

  void read_shape(const json& s, const std::string& where) {
    const std::string type = string(required(s, "type", where), where + ".type");
    const std::string name =
        s.contains("name") ? string(s["name"], where + ".name") : where + " (" + type + ")";
    const Mat4 to_world =
        s.contains("transform") ? transform(s["transform"], where + ".transform") : Mat4(1.0f);
    const int material = material_for_shape(s, where);
    const Rgb emission = color(s, "emission", where, Rgb(0.0f));
    const bool flip = boolean(s, "flip_normals", where, false);

    if (type == "sphere") {
      check_keys(s, where,
                 {"type", "name", "transform", "material", "emission", "flip_normals", "center",
                  "radius"});
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

  void read_environment(const json& e) {
    const std::string type = string(required(e, "type", "environment"), "environment.type");
    EnvironmentDesc& env = desc_.environment;
    if (type == "constant") {
      check_keys(e, "environment", {"type", "radiance"});
      env.kind = EnvironmentDesc::Kind::Constant;
      env.radiance = color(e, "radiance", "environment", Rgb(1.0f));
    } else if (type == "envmap") {
      check_keys(e, "environment", {"type", "file", "scale", "transform"});
      env.scale = number(e, "scale", "environment", 1.0f, loader::kNonNegativeRange);
      if (e.contains("transform"))
        env.to_world = transform(e["transform"], "environment.transform");
      loader::load_environment_map(
          env, path_,
          loader::resolve_path(path_,
                               string(required(e, "file", "environment"), "environment.file")));
    } else {
      fail("environment.type", "unknown environment type '" + type + "' (constant, envmap)");
    }
  }

  std::string path_;
  const SceneDefines& defines_;
  std::map<std::string, json> file_defaults_;
  std::map<std::string, MaterialDesc> named_materials_;
  int varying_textures_ = 0;
  SceneDescription desc_;
};

}  // namespace

SceneDescription load_json_scene(const std::string& path, const SceneDefines& defines) {
  return JsonSceneReader(path, defines).read();
}

}  // namespace emlt
