// pbrt-v4's materials mapped onto emlt's BSDFs. pbrt's surfaces scatter alike from both
// sides, so the one-sided models (diffuse, conductor, the coated ones) are made two-sided.
// pbrt's microfacet model is Trowbridge-Reitz (GGX) with alpha = sqrt(roughness) when
// remaproughness is on (its default), and perfectly smooth below alpha 1e-3. The layered
// materials (coateddiffuse, coatedconductor) are simulated stochastically by pbrt; emlt
// approximates them by Mitsuba's plastic and coating models (each an item of the verdict).
#include <fmt/format.h>

#include <cmath>

#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/materials.h"
#include "src/scene/loaders/loader_common.h"
#include "src/scene/loaders/pbrt_reader.h"

namespace emlt::pbrt {

namespace {

// Below this alpha pbrt treats a Trowbridge-Reitz surface as smooth.
constexpr float kSmoothAlpha = 1e-3f;

struct Roughness {
  TexturePtr u, v;  // alpha along u and v; null: smooth
};

}  // namespace

// Reads roughness (or uroughness and vroughness) with `prefix` ("", "interface.",
// "conductor.") as alphas.
static Roughness read_roughness(Reader& reader, const Where& at, const Params& params,
                                const std::string& prefix, const std::string& what) {
  const bool remap = params.get_bool("remaproughness", true);
  const std::string r = prefix + "roughness", ru = prefix + "uroughness",
                    rv = prefix + "vroughness";
  TexturePtr tu = reader.texture(params, params.has(ru) ? ru : r, Rgb(0.0f), true);
  TexturePtr tv = reader.texture(params, params.has(rv) ? rv : r, Rgb(0.0f), true);
  if (params.has(ru) || params.has(rv)) params.ignore(r);
  const auto cu = tu->constant(), cv = tv->constant();
  if (cu && cv) {
    const float au = remap ? std::sqrt(cu->x) : cu->x, av = remap ? std::sqrt(cv->x) : cv->x;
    if (std::max(au, av) < kSmoothAlpha) return {};
    return {make_constant_texture(Rgb(au)), au == av ? nullptr : make_constant_texture(Rgb(av))};
  }
  if (remap)
    reader.warn(at, what +
                        ": a textured roughness with remaproughness is not supported; the "
                        "texture is read as alpha");
  return {tu, tu == tv ? nullptr : tv};
}

int Reader::material(const Where& at, const std::string& type, const Params& params,
                     const std::string& name, bool* interface) {
  const std::string what = "material \"" + type + "\"";
  *interface = false;
  params.ignore("type");  // MakeNamedMaterial's
  for (const char* n : {"displacement", "normalmap"})
    if (const Param* p = params.get(n))
      warn({p->file, p->line}, what + " " + p->quoted() + " is not supported; ignored");
  // pbrt-v4 makes no material for "interface", "" and "none": the surface only bounds media.
  if (type == "interface" || type.empty() || type == "none") {
    *interface = true;
    report_unused(params, what);
    return -1;
  }
  bool textured = false;
  auto tex = [&](const std::string& n, const Rgb& fallback, bool is_float) {
    TexturePtr t = texture(params, n, fallback, is_float);
    textured = textured || !t->constant();
    return t;
  };
  // pbrt's eta: a float, a constant texture or a named glass spectrum (its index at the
  // helium d line, 587.6 nm; pbrt renders the dispersion).
  auto read_eta = [&](const std::string& n, float fallback) {
    const Param* p = params.get(n);
    if (!p) return fallback;
    if (p->type == "spectrum" && p->strings.size() == 1) {
      static const std::pair<const char*, float> kGlasses[] = {{"glass-BK7", 1.5168f},
                                                               {"glass-BAF10", 1.6700f},
                                                               {"glass-FK51A", 1.4866f},
                                                               {"glass-LASF9", 1.8503f}};
      for (const auto& [glass, eta] : kGlasses)
        if (p->strings[0] == glass) {
          warn({p->file, p->line},
               what + " " + p->quoted() + " \"" + glass +
                   fmt::format("\": its index at 587.6 nm ({:g}), without dispersion", eta),
               Divergence::Kind::Approximated);
          return eta;
        }
    }
    if (p->type == "float" && p->numbers.size() == 1) return float(p->numbers[0]);
    const std::optional<float> c = constant_float(params, n, fallback);
    if (!c) Params::fail(*p, "a varying index of refraction is not supported");
    return *c;
  };
  // A conductor's eta and k: named metal spectra ("metal-Cu-eta"), colours, or a
  // reflectance (pbrt: eta 1, k = 2 sqrt(r) / sqrt(1 - r)).
  auto read_conductor = [&](const std::string& prefix, Rgb* eta, Rgb* k) {
    const std::string ne = prefix + "eta", nk = prefix + "k", nr = prefix + "reflectance";
    if (params.has(nr)) {
      const TexturePtr r = tex(nr, Rgb(0.0f), false);
      const std::optional<Rgb> c = r->constant();
      if (!c)
        warn(at, what +
                     ": a textured conductor reflectance is not supported; its value at "
                     "uv (0, 0) is used");
      const Rgb refl = glm::clamp(c ? *c : r->eval(Vec2(0.0f)), Rgb(0.0f), Rgb(0.9999f));
      *eta = Rgb(1.0f);
      *k = 2.0f * glm::sqrt(refl) / glm::sqrt(Rgb(1.0f) - refl);
      params.ignore(ne);
      params.ignore(nk);
      return;
    }
    auto metal = [&](const std::string& n, const char* suffix, Rgb* out) {
      const Param* p = params.get(n);
      std::string named = p ? "" : std::string("metal-Cu-") + suffix;  // pbrt's default: copper
      if (p && p->type == "spectrum" && p->strings.size() == 1) named = p->strings[0];
      if (named.empty()) {
        *out = color(params, n, Rgb(1.0f));
        return;
      }
      const std::string tail = std::string("-") + suffix;
      Rgb preset_eta, preset_k;
      if (named.rfind("metal-", 0) != 0 || named.size() <= 6 + tail.size() ||
          named.compare(named.size() - tail.size(), tail.size(), tail) != 0 ||
          !conductor_preset(named.substr(6, named.size() - 6 - tail.size()), &preset_eta,
                            &preset_k)) {
        warn(at, what + ": spectrum \"" + named + "\" is not supported; copper is used");
        conductor_preset("Cu", &preset_eta, &preset_k);
      } else {
        warn(at, what + ": spectrum \"" + named + "\" as Mitsuba's RGB values for that metal",
             Divergence::Kind::Approximated);
      }
      *out = std::string(suffix) == "eta" ? preset_eta : preset_k;
    };
    metal(ne, "eta", eta);
    metal(nk, "k", k);
  };
  auto conductor_bsdf = [&](const std::string& prefix) {
    Rgb eta, k;
    read_conductor(prefix, &eta, &k);
    const Roughness rough = read_roughness(*this, at, params, prefix, what);
    textured = textured || (rough.u && !rough.u->constant());
    if (!rough.u) return make_conductor(eta, k);
    return make_rough_conductor(rough.u, eta, k, make_constant_texture(Rgb(1.0f)),
                                MicrofacetType::Ggx, rough.v);
  };

  BsdfPtr bsdf;
  if (type == "diffuse") {
    bsdf = make_two_sided(make_lambertian(tex("reflectance", Rgb(0.5f), false)));
  } else if (type == "conductor") {
    bsdf = make_two_sided(conductor_bsdf(""));
  } else if (type == "dielectric" || type == "thindielectric") {
    const float eta = read_eta("eta", 1.5f);
    if (!(eta > 0.0f)) fail(at, what + ": eta must be positive");
    // pbrt's outside medium is a vacuum (index 1).
    if (type == "thindielectric") {
      bsdf = make_thin_dielectric(eta, 1.0f);
    } else {
      const Roughness rough = read_roughness(*this, at, params, "", what);
      textured = textured || (rough.u && !rough.u->constant());
      bsdf = rough.u ? make_rough_dielectric(rough.u, eta, 1.0f, MicrofacetType::Ggx, Rgb(1.0f),
                                             Rgb(1.0f), rough.v)
                     : make_dielectric(eta, 1.0f);
    }
  } else if (type == "diffusetransmission") {
    const float scale = params.get_float("scale", 1.0f);
    TexturePtr r = tex("reflectance", Rgb(0.25f), false),
               t = tex("transmittance", Rgb(0.25f), false);
    if (scale != 1.0f) {
      r = make_scale_texture(r, Rgb(scale));
      t = make_scale_texture(t, Rgb(scale));
    }
    // f = R / pi on the side of the incoming light plus T / pi across: the sum of the two.
    bsdf = make_mixture({make_two_sided(make_lambertian(r)), make_diffuse_transmitter(t)},
                        {1.0f, 1.0f}, false);
  } else if (type == "coateddiffuse") {
    const float eta = read_eta("eta", 1.5f);
    const Roughness rough = read_roughness(*this, at, params, "", what);
    textured = textured || (rough.u && !rough.u->constant());
    if (rough.v)
      warn(at, what + ": anisotropic coating roughness is not supported; uroughness is used");
    const TexturePtr albedo = tex("albedo", Rgb(0.0f), false);
    if (!albedo->constant() || !is_black(*albedo->constant()))
      warn(at, what + ": a scattering coating (albedo) is not supported; the coating is clear");
    for (const char* n : {"thickness", "g", "maxdepth", "nsamples"}) params.ignore(n);
    bsdf = make_two_sided(make_rough_plastic(
        rough.u ? rough.u : make_constant_texture(Rgb(0.0f)), tex("reflectance", Rgb(0.5f), false),
        make_constant_texture(Rgb(1.0f)), eta, 1.0f, true, MicrofacetType::Ggx));
    warn(at,
         what +
             ": approximated by a (rough) plastic with internal reflections (Mitsuba's "
             "nonlinear model); pbrt simulates the layers stochastically",
         Divergence::Kind::Approximated);
  } else if (type == "coatedconductor") {
    const float eta = read_eta("interface.eta", 1.5f);
    const Roughness rough = read_roughness(*this, at, params, "interface.", what);
    textured = textured || (rough.u && !rough.u->constant());
    const TexturePtr albedo = tex("albedo", Rgb(0.0f), false);
    if (!albedo->constant() || !is_black(*albedo->constant()))
      warn(at, what + ": a scattering coating (albedo) is not supported; the coating is clear");
    for (const char* n : {"thickness", "g", "maxdepth", "nsamples"}) params.ignore(n);
    BsdfPtr base = conductor_bsdf("conductor.");
    // A layer of no thickness absorbs nothing.
    bsdf = rough.u ? make_rough_coating(base, rough.u, MicrofacetType::Ggx, eta, 1.0f, 0.0f)
                   : make_coating(base, eta, 1.0f, 0.0f);
    bsdf = make_two_sided(bsdf);
    warn(at,
         what +
             ": approximated by Mitsuba's (rough) coating over the conductor; pbrt "
             "simulates the layers stochastically",
         Divergence::Kind::Approximated);
  } else if (type == "mix") {
    const Param* p = params.get("materials");
    if (!p || p->type != "string" || p->strings.size() != 2)
      fail(at, what + " needs 'string materials' naming two materials");
    BsdfPtr parts[2];
    for (int i = 0; i < 2; ++i) {
      const auto it = named_materials_.find(p->strings[size_t(i)]);
      if (it == named_materials_.end())
        Params::fail(*p, "no material named \"" + p->strings[size_t(i)] + "\"");
      if (it->second < 0) Params::fail(*p, "\"" + p->strings[size_t(i)] + "\" is an interface");
      parts[i] = desc_.materials[size_t(it->second)].bsdf;
      textured = textured || desc_.materials[size_t(it->second)].textured;
    }
    // pbrt picks the second material with probability `amount` at each point: on average
    // the blend.
    bsdf = make_blend(tex("amount", Rgb(0.5f), true), parts[0], parts[1]);
  } else if (type == "measured" || type == "hair" || type == "subsurface") {
    for (const Param* p : params.unused()) p->used = true;
    warn(at, what + " is not supported; a diffuse 0.5 is used");
    bsdf = make_two_sided(make_lambertian(Rgb(0.5f)));
  } else {
    fail(at, "unknown material type '" + type + "'");
  }
  report_unused(params, what);
  return loader::material_index(desc_, MaterialDesc(name, bsdf, nullptr, nullptr, textured));
}

}  // namespace emlt::pbrt
