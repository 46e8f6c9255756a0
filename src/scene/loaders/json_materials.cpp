// The JSON scene format's materials and textures (scenes/README.md lists their keys).
#include <filesystem>

#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/materials.h"
#include "src/scene/loaders/json_scene_reader.h"
#include "src/scene/loaders/loader_common.h"

namespace emlt::json_scene {

TexturePtr JsonSceneReader::texture(const json& obj, const char* key, const std::string& where,
                                    Rgb fallback) {
  if (!obj.contains(key)) return make_constant_texture(fallback);
  const json& v = obj[key];
  if (!v.is_object()) return make_constant_texture(color(obj, key, where, fallback));
  TexturePtr t = texture_object(v, where + "." + key);
  if (!t->constant()) ++varying_textures_;
  return t;
}

TexturePtr JsonSceneReader::texture_object(const json& t, const std::string& where) {
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

TexturePtr JsonSceneReader::roughness(const json& m, const std::string& where, float fallback) {
  TexturePtr alpha = texture(m, "alpha", where, Rgb(fallback));
  if (auto c = alpha->constant(); c && !(c->x >= 0.0f)) fail(where + ".alpha", "must be >= 0");
  return alpha;
}

MicrofacetType JsonSceneReader::distribution(const json& m, const std::string& where) const {
  const std::string name =
      m.contains("distribution") ? string(m["distribution"], where + ".distribution") : "ggx";
  if (name == "ggx") return MicrofacetType::Ggx;
  if (name == "beckmann") return MicrofacetType::Beckmann;
  if (name == "phong") return MicrofacetType::Phong;
  fail(where + ".distribution", "expected \"ggx\", \"beckmann\" or \"phong\"");
}

float JsonSceneReader::ior(const json& obj, const char* key, const std::string& where,
                           float fallback) const {
  if (!obj.contains(key)) return fallback;
  if (obj[key].is_string()) {
    const std::string name = obj[key].get<std::string>();
    if (auto value = loader::named_ior(name)) return *value;
    fail(where + "." + key, "unknown index of refraction name '" + name + "'");
  }
  return number(obj[key], where + "." + key, loader::kPositiveRange);
}

void JsonSceneReader::conductor_ior(const json& m, const std::string& where, Rgb* eta,
                                    Rgb* k) const {
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

MaterialDesc JsonSceneReader::read_material(const json& spec, const std::string& where) {
  const json& m = object(spec, where);
  const std::string type = string(required(m, "type", where), where + ".type");
  const int textures_before = varying_textures_;
  BsdfPtr bsdf;
  bool opaque = true;
  if (type == "diffuse") {
    check_keys(m, where, {"type", "reflectance", "two_sided", "opacity", "bump"});
    bsdf = make_lambertian(texture(m, "reflectance", where, Rgb(0.5f)));
  } else if (type == "roughdiffuse") {
    check_keys(m, where,
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
    const std::optional<WardVariant> variant = parse_ward_variant(name);
    if (!variant) fail(where + ".variant", "expected \"ward\", \"ward-duer\" or \"balanced\"");
    const float alpha =
        m.contains("alpha") ? number(m["alpha"], where + ".alpha", loader::kPositiveRange) : 0.1f;
    TexturePtr alpha_u = texture(m, "alpha_u", where, Rgb(alpha));
    TexturePtr alpha_v = texture(m, "alpha_v", where, Rgb(alpha));
    for (const auto& [key, a] : {std::pair{"alpha_u", alpha_u}, std::pair{"alpha_v", alpha_v}})
      if (auto c = a->constant(); c && !(c->x > 0.0f)) fail(where + "." + key, "must be > 0");
    bsdf =
        make_ward(*variant, alpha_u, alpha_v, texture(m, "specular_reflectance", where, Rgb(0.2f)),
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
    bsdf = make_rough_plastic(alpha, texture(m, "diffuse_reflectance", where, Rgb(0.5f)),
                              texture(m, "specular_reflectance", where, Rgb(1.0f)),
                              ior(m, "int_ior", where, 1.49f), ior(m, "ext_ior", where, 1.000277f),
                              boolean(m, "nonlinear", where, false),
                              type == "plastic" ? MicrofacetType::Ggx : distribution(m, where));
  } else if (type == "mixture" || type == "blend") {
    // Weighted sums of nested materials (Mitsuba's mixturebsdf and blendbsdf); each part
    // keeps its own sidedness, and opacity and bump belong to the whole surface.
    const bool mixture = type == "mixture";
    if (mixture)
      check_keys(m, where,
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
      if (part.opacity || part.bump) fail(at, "a part of a " + type + " takes no opacity or bump");
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

}  // namespace emlt::json_scene
