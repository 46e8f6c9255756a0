// Mitsuba 0.6 <bsdf> elements mapped onto the built-in BSDFs. Mitsuba's defaults are kept
// (diffuse reflectance 0.5, intIOR bk7 for dielectrics, polypropylene for plastics, Cu
// conductors, alpha 0.1, Beckmann distribution) so that a scene renders like it does in
// Mitsuba. `mask` and `bumpmap` become the material's opacity and bump textures;
// `coating` and `roughcoating` wrap their nested BSDF in Mitsuba's layer model, and
// `normalmap` in a wrapper that tilts the frame it sees.
#include <cctype>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "emlt/core/error.h"
#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/materials.h"
#include "src/scene/loaders/loader_common.h"
#include "src/scene/loaders/mitsuba_parser.h"

namespace emlt::mitsuba {

namespace {

class BsdfReader {
 public:
  BsdfReader(const Document& doc, NamedObjects& named) : doc_(doc), named_(named) {}

  MaterialDesc read(pugi::xml_node node) {
    if (std::string(node.name()) == "ref") {
      const std::string id = doc_.attribute(node, "id");
      auto it = named_.bsdfs.find(id);
      if (it == named_.bsdfs.end()) doc_.fail(node, "unknown reference id '" + id + "'");
      return it->second;
    }
    const std::string type = doc_.attribute(node, "type");
    Properties props(doc_, node);
    const int textures_before = varying_textures_;
    const int vertex_color_textures_before = vertex_color_textures_;
    MaterialDesc material = build(type, node, props);
    material.textured |= varying_textures_ > textures_before || material.bump;
    material.reads_vertex_colors |= vertex_color_textures_ > vertex_color_textures_before;
    props.warn_unused();
    if (doc_.has_attribute(node, "id")) {
      material.name = doc_.attribute(node, "id");
      named_.bsdfs[material.name] = material;
    }
    return material;
  }

 private:
  // A parameter that may be a texture; counts the ones that vary over the surface and,
  // apart, those that read the mesh's vertex colours (which do not vary with uv).
  TexturePtr texture(Properties& props, const char* name, const Rgb& fallback) {
    TexturePtr t = props.get_texture(name, fallback, named_);
    if (t->reads_vertex_colors())
      ++vertex_color_textures_;
    else if (!t->constant())
      ++varying_textures_;
    return t;
  }

  float ior(Properties& props, const char* name, float fallback, pugi::xml_node node) {
    if (!props.has(name)) return fallback;
    // Mitsuba accepts a number (<float>) or a material name (<string>) for an IOR.
    if (props.kind_of(name) != "string")
      return props.get_float(name, fallback, loader::kPositiveRange);
    const std::string text = props.get_string(name, "");
    if (auto value = loader::named_ior(text)) return *value;
    doc_.fail(node, "unknown index of refraction '" + text + "'");
  }

  // Mitsuba's conductor parameters, divided by the exterior IOR like Mitsuba does.
  void conductor_ior(Properties& props, pugi::xml_node node, Rgb* eta, Rgb* k) {
    // Mitsuba 3 changed the default: no material is a perfect mirror (eta 0, k 1), not Cu;
    // and it reads no exterior IOR (eta and k are relative to the outside as given).
    const bool mitsuba3 = doc_.mitsuba3();
    const bool no_material = mitsuba3 && props.get_string("material", "none") == "none";
    if (props.has("eta") || props.has("k") || no_material) {
      *eta = props.get_color("eta", Rgb(0.0f));
      *k = props.get_color("k", Rgb(1.0f));
      if (props.has("material") && !no_material)
        doc_.warn(node, "'material' ignored because eta/k are given", Document::Warning::Note);
      props.ignore({"material"});
    } else {
      const std::string material = props.get_string("material", "Cu");
      if (!conductor_preset(material, eta, k))
        doc_.fail(node, "unknown conductor material '" + material + "'");
      if (mitsuba3)
        doc_.warn(props.node_of("material"),
                  "conductor material '" + material +
                      "' given Mitsuba 0.6's RGB eta and k; Mitsuba 3 converts the measured "
                      "spectra its own way (a few per cent apart)",
                  Document::Warning::Approximated);
    }
    // Mitsuba's default exterior is "air" (1.000277), for named and explicit eta/k alike.
    const float ext_eta = mitsuba3 ? 1.0f : ior(props, "extEta", 1.000277f, node);
    // Mitsuba's Fresnel term depends on eta^2 and k^2 only, so a negative component (the
    // red eta of the AlSb presets) acts as its magnitude; the conductor BSDFs would clamp
    // it to 0 instead.
    *eta = glm::abs(*eta / ext_eta);
    *k = glm::abs(*k / ext_eta);
  }

  MicrofacetType distribution(Properties& props, pugi::xml_node node) {
    // Mitsuba's choice between sampling all normals and the visible ones only.
    props.note_sampling_only({"sampleVisible"}, "how Mitsuba samples the microfacet normals");
    std::string name = props.get_string("distribution", "beckmann");
    for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));  // as Mitsuba
    if (doc_.mitsuba3() && name != "ggx" && name != "beckmann")
      doc_.warn(props.node_of("distribution"),
                "microfacet distribution '" + name +
                    "' is not Mitsuba 3's (it has beckmann and ggx, and refuses this file); "
                    "read as Mitsuba 0.6's");
    if (name == "ggx") return MicrofacetType::Ggx;
    if (name == "phong" || name == "as") return MicrofacetType::Phong;  // "as": Ashikhmin-Shirley
    if (name != "beckmann")
      doc_.warn(node,
                "microfacet distribution '" + name +
                    "' is not supported; using Beckmann with the same alpha",
                Document::Warning::Approximated);
    return MicrofacetType::Beckmann;
  }

  // Mitsuba's roughness: `alpha`, or both `alphaU` (along dp/du) and `alphaV`; either may
  // be a texture. `v` is null when the roughness is isotropic.
  struct Roughness {
    TexturePtr u, v;
  };
  Roughness roughness(Properties& props, pugi::xml_node node) {
    if (!props.has("alphaU") && !props.has("alphaV")) return {alpha(props, node), nullptr};
    // Mitsuba refuses both of these.
    if (props.has("alpha")) doc_.fail(node, "give either 'alpha' or 'alphaU'/'alphaV'");
    if (!props.has("alphaU") || !props.has("alphaV"))
      doc_.fail(node, "'alphaU' and 'alphaV' must both be given");
    TexturePtr u = texture(props, "alphaU", Rgb(0.1f)), v = texture(props, "alphaV", Rgb(0.1f));
    for (const TexturePtr& a : {u, v})
      if (auto c = a->constant(); c && !((c->x + c->y + c->z) >= 0.0f))
        doc_.fail(node, "alphaU and alphaV must not be negative");
    return {u, v};
  }

  TexturePtr alpha(Properties& props, pugi::xml_node node) {
    if (props.has("alphaU") || props.has("alphaV")) {
      // roughplastic and roughcoating come here with alphaU/alphaV; Mitsuba refuses them
      // unequal (roughcoating has refused them already).
      const float a = props.get_float("alpha", 0.1f);
      const float u = props.get_float("alphaU", a), v = props.get_float("alphaV", a);
      if (u != v)
        doc_.warn(node,
                  "anisotropic roughness approximated by the mean of alphaU and alphaV "
                  "(Mitsuba's roughplastic refuses it)",
                  Document::Warning::Approximated);
      if (!(u + v > 0.0f)) doc_.fail(node, "alpha must be positive");
      return make_constant_texture(Rgb(0.5f * (u + v)));
    }
    TexturePtr a = texture(props, "alpha", Rgb(0.1f));
    if (auto c = a->constant(); c && !((c->x + c->y + c->z) > 0.0f))
      doc_.fail(node, "alpha must be positive");
    return a;
  }

  // Mitsuba's ensureEnergyConservation (on unless the scene turns it off): when the largest
  // component of a reflectance, or of the sum of a BSDF's reflectances, exceeds 1, they are
  // all scaled by 0.99 over that maximum. A constant's maximum is known here and applied; a
  // texture's is not (Mitsuba takes a bitmap's largest texel), so where a texture's lookups
  // over a grid of its period reach above 1 the difference is reported, not guessed at.
  void conserve_energy(Properties& props, pugi::xml_node node,
                       std::initializer_list<TexturePtr*> reflectances) {
    // Mitsuba 3 scales nothing (and reads no such parameter).
    if (doc_.mitsuba3() || !props.get_boolean("ensureEnergyConservation", true)) return;
    Rgb sum(0.0f);
    bool textured = false;
    for (TexturePtr* r : reflectances) {
      if (const std::optional<Rgb> c = (*r)->constant()) {
        sum += glm::max(*c, Rgb(0.0f));
        continue;
      }
      textured = true;
      constexpr int kSide = 128;
      Rgb largest(0.0f);
      for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i)
          largest = glm::max(largest, (*r)->eval(Vec2((i + 0.5f) / kSide, (j + 0.5f) / kSide)));
      sum += largest;
    }
    const float maximum = glm::max(sum.x, glm::max(sum.y, sum.z));
    if (!(maximum > 1.0f)) return;
    if (textured) {
      doc_.warn(node,
                "textured reflectance reaching " + std::to_string(maximum) +
                    " left as given; Mitsuba scales it to conserve energy "
                    "(ensureEnergyConservation: 0.99 over its largest texel)",
                Document::Warning::Approximated);
      return;
    }
    const float scale = 0.99f / maximum;
    for (TexturePtr* r : reflectances) *r = make_constant_texture(*(*r)->constant() * scale);
    doc_.warn(node,
              "reflectance above 1 scaled by " + std::to_string(scale) +
                  " to conserve energy, as Mitsuba does (ensureEnergyConservation)",
              Document::Warning::Note);
  }

  // A dielectric's specularReflectance and specularTransmittance (numbers or textures), each
  // scaled on its own to conserve energy, as Mitsuba's dielectrics do.
  std::pair<TexturePtr, TexturePtr> specular_tints(Properties& props, pugi::xml_node node) {
    TexturePtr reflectance = texture(props, "specularReflectance", Rgb(1.0f));
    TexturePtr transmittance = texture(props, "specularTransmittance", Rgb(1.0f));
    conserve_energy(props, node, {&reflectance});
    conserve_energy(props, node, {&transmittance});
    return {reflectance, transmittance};
  }

  // The nested BSDF of a wrapper; unnamed <texture> children are left to `textures`.
  MaterialDesc nested(pugi::xml_node node, Properties& props,
                      std::vector<pugi::xml_node>* textures = nullptr) {
    pugi::xml_node inner;
    for (pugi::xml_node child : props.objects()) {
      const std::string kind = child.name();
      if (textures && kind == "texture") {
        textures->push_back(child);
        continue;
      }
      if (kind != "bsdf" && kind != "ref") {
        doc_.warn(child,
                  "unsupported element <" + kind + "> inside " + doc_.describe(node) + " ignored");
        continue;
      }
      if (inner)
        doc_.warn(child, "only the first nested BSDF of " + doc_.describe(node) + " is used");
      else
        inner = child;
    }
    if (!inner) doc_.fail(node, doc_.describe(node) + " needs a nested <bsdf>");
    return read(inner);
  }

  void no_children(pugi::xml_node node, Properties& props) {
    for (pugi::xml_node child : props.objects())
      doc_.warn(child, "unsupported element <" + std::string(child.name()) + "> inside " +
                           doc_.describe(node) + " ignored");
  }

  MaterialDesc wrapper(const std::string& type, pugi::xml_node node, Properties& props) {
    // Every Mitsuba BSDF reads ensureEnergyConservation; these wrappers have nothing to scale.
    if (type == "twosided" || type == "bumpmap" || type == "normalmap")
      props.get_boolean("ensureEnergyConservation", true);
    if (type == "twosided") {
      MaterialDesc inner = nested(node, props);
      if (inner.bsdf->lobes() & kLobeTransmission) {
        if (doc_.mitsuba3())  // allow_transmission aside, Mitsuba 3 refuses it
          doc_.warn(node,
                    "<twosided> around a transmissive BSDF is refused by Mitsuba 3; left out");
        else
          doc_.warn(node, "<twosided> around a transmissive BSDF has no effect; left out",
                    Document::Warning::Note);
        return inner;
      }
      inner.bsdf = make_two_sided(inner.bsdf);
      return inner;
    }
    if (type == "mask") {
      TexturePtr opacity = texture(props, "opacity", Rgb(0.5f));
      conserve_energy(props, node, {&opacity});
      MaterialDesc inner = nested(node, props);
      if (inner.opacity)
        doc_.warn(node, "nested masks: only the outer opacity is used",
                  Document::Warning::Approximated);
      inner.opacity = opacity;
      inner.textured |= !opacity->constant() && !opacity->reads_vertex_colors();
      return inner;
    }
    if (type == "bumpmap") {
      std::vector<pugi::xml_node> textures;
      MaterialDesc inner = nested(node, props, &textures);
      TexturePtr height;
      for (const std::string& name : props.names_of_kind("texture"))
        if (!height) height = props.get_texture(name, Rgb(0.0f), named_);
      for (const std::string& name : props.names_of_kind("ref"))
        if (!height) height = props.get_texture(name, Rgb(0.0f), named_);
      for (pugi::xml_node t : textures)
        if (!height) height = read_texture(doc_, t, named_);
      if (!height) doc_.fail(node, "<bsdf type=\"bumpmap\"> needs a nested <texture>");
      if (doc_.mitsuba3()) height = mitsuba3_bump_height(node, props, height);
      if (inner.bump)
        doc_.warn(node, "nested bump maps: only the outer one is used",
                  Document::Warning::Approximated);
      inner.bump = height;
      inner.textured = true;
      return inner;
    }
    if (type == "coating" || type == "roughcoating") return coating(type, node, props);
    return normal_map(node, props);
  }

  // Mitsuba's `normalmap`: its one texture (of any name) holds tangent-space normals.
  MaterialDesc normal_map(pugi::xml_node node, Properties& props) {
    std::vector<pugi::xml_node> textures;
    MaterialDesc inner = nested(node, props, &textures);
    TexturePtr normals;
    for (const char* kind : {"texture", "ref"})
      for (const std::string& name : props.names_of_kind(kind))
        if (!normals) normals = props.get_texture(name, Rgb(0.0f), named_);
    for (pugi::xml_node t : textures) {
      if (normals) break;
      // Mitsuba 0.6 refuses a bitmap read with its default curve: normals are linear.
      bool gamma = false;
      for (pugi::xml_node child : t.children())
        gamma |= std::string(child.attribute("name").as_string()) == "gamma";
      if (!doc_.mitsuba3() && std::string(t.attribute("type").as_string()) == "bitmap" && !gamma)
        doc_.fail(t,
                  "a bitmap normal map needs an explicit 'gamma' (Mitsuba refuses it without; "
                  "usually <float name=\"gamma\" value=\"1\"/>)");
      normals = read_texture(doc_, t, named_);
    }
    if (!normals) doc_.fail(node, "<bsdf type=\"normalmap\"> needs a nested <texture>");
    if (doc_.mitsuba3()) {
      // Mitsuba 3 by default turns a normal facing away from the viewer and darkens the
      // shading where the normal leans far from the true one; emlt does as 0.6 does.
      const bool flip = props.get_boolean("flip_invalid_normals", true);
      const bool shadowing = props.get_boolean("use_shadowing_function", true);
      if (flip || shadowing)
        doc_.warn(node,
                  std::string("Mitsuba 3's normal map ") +
                      (shadowing ? "shadowing function (use_shadowing_function)" : "") +
                      (shadowing && flip ? " and " : "") +
                      (flip ? "normal flipping (flip_invalid_normals)" : "") +
                      " not supported; perturbed as Mitsuba 0.6 does",
                  Document::Warning::Approximated);
    }
    if (inner.bump)
      doc_.warn(node, "a bump map inside a normal map: both tilt the normal, the bump first",
                Document::Warning::Approximated);
    inner.bsdf = make_normal_map(inner.bsdf, normals);
    inner.textured = true;
    return inner;
  }

  // Mitsuba's `coating` and `roughcoating`: a dielectric layer over the nested BSDF. Mitsuba
  // reads sigmaA and (rough) alpha as numbers or textures, specularReflectance as a colour
  // only, and refuses a textured one, an anisotropic roughness and equal IORs.
  MaterialDesc coating(const std::string& type, pugi::xml_node node, Properties& props) {
    const float int_ior = ior(props, "intIOR", 1.5046f, node);    // bk7
    const float ext_ior = ior(props, "extIOR", 1.000277f, node);  // air
    if (int_ior == ext_ior) doc_.fail(node, "intIOR and extIOR of a coating must differ");
    const float thickness = props.get_float("thickness", 1.0f);
    TexturePtr sigma_a = texture(props, "sigmaA", Rgb(0.0f));
    const std::string specular_kind = props.kind_of("specularReflectance");
    if (specular_kind == "texture" || specular_kind == "ref")
      doc_.fail(props.node_of("specularReflectance"),
                "the 'specularReflectance' of a " + type +
                    " must be a colour (Mitsuba refuses a texture for it)");
    TexturePtr specular = make_constant_texture(props.get_color("specularReflectance", Rgb(1.0f)));
    conserve_energy(props, node, {&specular});
    const Rgb specular_value = *specular->constant();
    MicrofacetType dist = MicrofacetType::Beckmann;
    TexturePtr a;
    if (type == "roughcoating") {
      dist = distribution(props, node);
      // Mitsuba reads alphaU/alphaV as its other rough BSDFs do, and refuses them unequal.
      if (props.has("alphaU") || props.has("alphaV")) {
        if (props.has("alpha")) doc_.fail(node, "give either 'alpha' or 'alphaU'/'alphaV'");
        if (!props.has("alphaU") || !props.has("alphaV"))
          doc_.fail(node, "'alphaU' and 'alphaV' must both be given");
        if (props.get_float("alphaU", 0.1f) != props.get_float("alphaV", 0.1f))
          doc_.fail(node,
                    "roughcoating does not support an anisotropic roughness (alphaU unlike "
                    "alphaV; Mitsuba refuses it too)");
      }
      a = alpha(props, node);
    }
    MaterialDesc inner = nested(node, props);
    if (inner.opacity || inner.bump)
      doc_.warn(node,
                "a mask or bump map inside " + doc_.describe(node) +
                    " applies to the whole surface, coating included",
                Document::Warning::Approximated);
    inner.bsdf = a ? make_rough_coating(inner.bsdf, a, dist, int_ior, ext_ior, thickness, sigma_a,
                                        specular_value)
                   : make_coating(inner.bsdf, int_ior, ext_ior, thickness, sigma_a, specular_value);
    return inner;
  }

  // Mitsuba 3's bumpmap scales the height by its `scale` (0.6 nests a scale texture), and
  // by default darkens the shading where the bumped normal leans far from the true one
  // (use_shadowing_function), which emlt does not.
  TexturePtr mitsuba3_bump_height(pugi::xml_node node, Properties& props, TexturePtr height) {
    // Mitsuba 3 also turns a bumped normal that faces away from the viewer back
    // (flip_invalid_normals); emlt bends normals as 0.6 does.
    const float scale = props.get_float("scale", 1.0f);
    const bool shadowing = props.get_boolean("use_shadowing_function", true);
    const bool flip = props.get_boolean("flip_invalid_normals", true);
    if (shadowing || flip)
      doc_.warn(node,
                std::string("Mitsuba 3's bump map ") +
                    (shadowing ? "shadowing function (use_shadowing_function)" : "") +
                    (shadowing && flip ? " and " : "") +
                    (flip ? "normal flipping (flip_invalid_normals)" : "") +
                    " not supported; bumped as Mitsuba 0.6 bumps",
                Document::Warning::Approximated);
    return scale == 1.0f ? height : make_scale_texture(height, Rgb(scale));
  }

  // The nested BSDFs of a mixturebsdf or blendbsdf, in the file's order. A nested mask or
  // bump map is a property of the whole surface in emlt, not of one part of a sum.
  std::vector<BsdfPtr> parts(pugi::xml_node node, Properties& props) {
    std::vector<BsdfPtr> bsdfs;
    for (pugi::xml_node child : props.objects()) {
      const std::string kind = child.name();
      if (kind != "bsdf" && kind != "ref") {
        doc_.warn(child,
                  "unsupported element <" + kind + "> inside " + doc_.describe(node) + " ignored");
        continue;
      }
      const MaterialDesc part = read(child);
      if (part.opacity || part.bump)
        doc_.warn(child,
                  "a mask or bump map inside " + doc_.describe(node) +
                      " is not supported; its nested BSDF is used alone",
                  Document::Warning::Approximated);
      bsdfs.push_back(part.bsdf);
    }
    return bsdfs;
  }

  BsdfPtr mixture(pugi::xml_node node, Properties& props) {
    const std::vector<BsdfPtr> bsdfs = parts(node, props);
    if (!props.has("weights")) doc_.fail(node, "<bsdf type=\"mixturebsdf\"> needs 'weights'");
    const pugi::xml_node weights_node = props.node_of("weights");
    // Mitsuba separates the weights by spaces, commas or semicolons.
    std::string text = props.get_string("weights", "");
    for (char& c : text)
      if (c == ';') c = ' ';
    const std::vector<float> weights = doc_.to_floats(weights_node, text);
    if (weights.empty()) doc_.fail(weights_node, "'weights' of a mixturebsdf lists no weight");
    if (weights.size() != bsdfs.size())
      doc_.fail(node, "mixturebsdf has " + std::to_string(bsdfs.size()) + " nested BSDFs but " +
                          std::to_string(weights.size()) + " weights");
    float total = 0.0f;
    for (float w : weights) {
      if (w < 0.0f) doc_.fail(weights_node, "'weights' of a mixturebsdf must not be negative");
      total += w;
    }
    if (!(total > 0.0f))
      doc_.fail(weights_node, "'weights' of a mixturebsdf must sum to more than 0");
    const bool conserve = props.get_boolean("ensureEnergyConservation", true);
    if (conserve && total > 1.0f)
      doc_.warn(node,
                "weights summing to " + std::to_string(total) +
                    " divided by their sum to conserve energy, as Mitsuba does "
                    "(ensureEnergyConservation)",
                Document::Warning::Note);
    return make_mixture(bsdfs, weights, conserve);
  }

  BsdfPtr blend(pugi::xml_node node, Properties& props) {
    const std::vector<BsdfPtr> bsdfs = parts(node, props);
    if (bsdfs.size() != 2)
      doc_.fail(node, "blendbsdf needs exactly two nested BSDFs (it has " +
                          std::to_string(bsdfs.size()) + ")");
    // A number, or a texture given as <texture name="weight"> or <ref name="weight">.
    TexturePtr weight = texture(props, "weight", Rgb(0.5f));
    // Read by every Mitsuba BSDF; a blend's weights always sum to 1, so it changes nothing.
    props.get_boolean("ensureEnergyConservation", true);
    return make_blend(weight, bsdfs[0], bsdfs[1]);
  }

  MaterialDesc build(const std::string& type, pugi::xml_node node, Properties& props) {
    if (type == "twosided" || type == "mask" || type == "bumpmap" || type == "coating" ||
        type == "roughcoating" || type == "normalmap")
      return wrapper(type, node, props);
    if (type == "mixturebsdf") return MaterialDesc("", mixture(node, props));
    if (type == "blendbsdf") return MaterialDesc("", blend(node, props));
    no_children(node, props);
    return MaterialDesc("", scattering(type, node, props));
  }

  BsdfPtr scattering(const std::string& type, pugi::xml_node node, Properties& props) {
    // Exporters write roughness onto smooth materials, whose Mitsuba plugins never read it:
    // ignoring it is what Mitsuba does too.
    if (type == "dielectric" || type == "thindielectric" || type == "conductor" ||
        type == "plastic") {
      for (const char* name : {"alpha", "alphaU", "alphaV", "distribution"}) {
        if (!props.has(name)) continue;
        props.ignore({name});
        doc_.warn(node,
                  std::string("parameter '") + name + "' of a smooth " + type +
                      " ignored, as Mitsuba does (it reads no roughness)",
                  Document::Warning::Note);
      }
    }
    if (type == "diffuse") {
      TexturePtr reflectance = texture(props, "reflectance", Rgb(0.5f));
      conserve_energy(props, node, {&reflectance});
      return make_lambertian(reflectance);
    }
    if (type == "roughdiffuse") {
      // Mitsuba reads `diffuseReflectance` too, when `reflectance` is not given.
      const char* reflectance_name = props.has("reflectance") || !props.has("diffuseReflectance")
                                         ? "reflectance"
                                         : "diffuseReflectance";
      TexturePtr reflectance = texture(props, reflectance_name, Rgb(0.5f));
      TexturePtr a = texture(props, "alpha", Rgb(0.2f));
      if (auto c = a->constant(); c && !((c->x + c->y + c->z) >= 0.0f))
        doc_.fail(props.node_of("alpha"), "'alpha' of a roughdiffuse must not be negative");
      const bool fast = props.get_boolean("useFastApprox", false);
      conserve_energy(props, node, {&reflectance});
      return make_rough_diffuse(reflectance, a, fast);
    }
    if (type == "difftrans") {
      // Mitsuba reads `diffuseTransmittance` too, when `transmittance` is not given.
      const char* name = props.has("transmittance") || !props.has("diffuseTransmittance")
                             ? "transmittance"
                             : "diffuseTransmittance";
      TexturePtr transmittance = texture(props, name, Rgb(0.5f));
      conserve_energy(props, node, {&transmittance});
      return make_diffuse_transmitter(transmittance);
    }
    if (type == "phong") {
      TexturePtr exponent = texture(props, "exponent", Rgb(30.0f));
      if (auto c = exponent->constant(); c && !((c->x + c->y + c->z) >= 0.0f))
        doc_.fail(props.node_of("exponent"), "'exponent' of a phong must not be negative");
      TexturePtr specular = texture(props, "specularReflectance", Rgb(0.2f));
      TexturePtr diffuse = texture(props, "diffuseReflectance", Rgb(0.5f));
      conserve_energy(props, node, {&specular, &diffuse});
      return make_phong(exponent, specular, diffuse);
    }
    if (type == "ward") {
      std::string name = props.get_string("variant", "balanced");
      for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));  // as Mitsuba
      const std::optional<WardVariant> variant = parse_ward_variant(name);
      if (!variant)
        doc_.fail(props.node_of("variant"),
                  "unknown ward variant '" + name + "' (ward, ward-duer or balanced)");
      // `alpha` (a number) is the default of both alphaU and alphaV, which may be textures.
      const float alpha = props.get_float("alpha", 0.1f, loader::kPositiveRange);
      TexturePtr alpha_u = texture(props, "alphaU", Rgb(alpha));
      TexturePtr alpha_v = texture(props, "alphaV", Rgb(alpha));
      for (const auto& [which, a] : {std::pair{"alphaU", alpha_u}, std::pair{"alphaV", alpha_v}})
        if (auto c = a->constant(); c && !((c->x + c->y + c->z) > 0.0f))
          doc_.fail(props.node_of(which),
                    std::string("'") + which + "' of a ward must be positive");
      TexturePtr specular = texture(props, "specularReflectance", Rgb(0.2f));
      TexturePtr diffuse = texture(props, "diffuseReflectance", Rgb(0.5f));
      conserve_energy(props, node, {&specular, &diffuse});
      return make_ward(*variant, alpha_u, alpha_v, specular, diffuse);
    }
    if (type == "dielectric" || type == "thindielectric") {
      const float int_ior = ior(props, "intIOR", 1.5046f, node);
      const float ext_ior = ior(props, "extIOR", 1.000277f, node);
      auto [reflectance, transmittance] = specular_tints(props, node);
      return type == "dielectric"
                 ? make_dielectric(int_ior, ext_ior, reflectance, transmittance)
                 : make_thin_dielectric(int_ior, ext_ior, reflectance, transmittance);
    }
    if (type == "roughdielectric") {
      const MicrofacetType dist = distribution(props, node);
      const Roughness a = roughness(props, node);
      const float int_ior = ior(props, "intIOR", 1.5046f, node);
      const float ext_ior = ior(props, "extIOR", 1.000277f, node);
      auto [reflectance, transmittance] = specular_tints(props, node);
      return make_rough_dielectric(a.u, int_ior, ext_ior, dist, reflectance, transmittance, a.v);
    }
    if (type == "conductor") {
      Rgb eta, k;
      conductor_ior(props, node, &eta, &k);
      TexturePtr specular = texture(props, "specularReflectance", Rgb(1.0f));
      conserve_energy(props, node, {&specular});
      return make_conductor(eta, k, specular);
    }
    if (type == "roughconductor") {
      const MicrofacetType dist = distribution(props, node);
      const Roughness a = roughness(props, node);
      Rgb eta, k;
      conductor_ior(props, node, &eta, &k);
      TexturePtr specular = texture(props, "specularReflectance", Rgb(1.0f));
      conserve_energy(props, node, {&specular});
      return make_rough_conductor(a.u, eta, k, specular, dist, a.v);
    }
    if (type == "plastic" || type == "roughplastic") {
      MicrofacetType dist = MicrofacetType::Ggx;
      TexturePtr a = make_constant_texture(Rgb(0.0f));
      if (type == "roughplastic") {
        dist = distribution(props, node);
        a = alpha(props, node);
      }
      const bool nonlinear = props.get_boolean("nonlinear", false);
      const float int_ior = ior(props, "intIOR", 1.49f, node);
      const float ext_ior = ior(props, "extIOR", 1.000277f, node);
      TexturePtr diffuse = texture(props, "diffuseReflectance", Rgb(0.5f));
      TexturePtr specular = texture(props, "specularReflectance", Rgb(1.0f));
      // Mitsuba scales each of the two on its own, not their sum.
      conserve_energy(props, node, {&specular});
      conserve_energy(props, node, {&diffuse});
      return make_rough_plastic(a, diffuse, specular, int_ior, ext_ior, nonlinear, dist);
    }
    if (type == "principled" && doc_.mitsuba3()) {
      // Disney's diffuse lobe is not Lambertian (retro-reflection, sheen) and its specular
      // lobe is not any one BSDF here: no parameter set of it maps exactly.
      doc_.warn(node,
                "<bsdf type=\"principled\"> is not supported; rendered as a diffuse of its "
                "base_color (its other parameters ignored)");
      TexturePtr base = texture(props, "base_color", Rgb(0.5f));
      props.ignore_rest();  // one item for the whole BSDF
      return make_lambertian(base);
    }
    doc_.warn(node, "unsupported BSDF type '" + type + "'; using a diffuse of reflectance 0.5");
    props.ignore({"specularReflectance", "exponent", "alpha", "alphaU", "alphaV"});
    for (const char* name : {"reflectance", "diffuseReflectance"})
      if (props.has(name)) return make_lambertian(texture(props, name, Rgb(0.5f)));
    return make_lambertian(Rgb(0.5f));
  }

  const Document& doc_;
  NamedObjects& named_;
  int varying_textures_ = 0;
  int vertex_color_textures_ = 0;
};

}  // namespace

MaterialDesc read_bsdf(const Document& doc, pugi::xml_node node, NamedObjects& named,
                       std::vector<std::string>&) {
  return BsdfReader(doc, named).read(node);
}

}  // namespace emlt::mitsuba
