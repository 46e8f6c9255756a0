// Mitsuba 0.6 <bsdf> elements mapped onto the built-in BSDFs. Mitsuba's defaults are kept
// (diffuse reflectance 0.5, intIOR bk7 for dielectrics, polypropylene for plastics, Cu
// conductors, alpha 0.1, Beckmann distribution) so that a scene renders like it does in
// Mitsuba. This file holds the reader itself: the parameters every family shares, the
// nesting of BSDFs, and the one dispatch from a plugin type to the reader of its family
// (mitsuba_bsdf_reader.h lists the files that hold them).
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "emlt/scene/materials.h"
#include "src/scene/loaders/loader_common.h"
#include "src/scene/loaders/mitsuba_bsdf_reader.h"

namespace emlt::mitsuba {

MaterialDesc BsdfReader::read(pugi::xml_node node) {
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

TexturePtr BsdfReader::texture(Properties& props, const char* name, const Rgb& fallback) {
  TexturePtr t = props.get_texture(name, fallback, named_);
  if (t->reads_vertex_colors())
    ++vertex_color_textures_;
  else if (!t->constant())
    ++varying_textures_;
  return t;
}

float BsdfReader::ior(Properties& props, const char* name, float fallback, pugi::xml_node node) {
  if (!props.has(name)) return fallback;
  // Mitsuba accepts a number (<float>) or a material name (<string>) for an IOR.
  if (props.kind_of(name) != "string")
    return props.get_float(name, fallback, loader::kPositiveRange);
  const std::string text = props.get_string(name, "");
  if (auto value = loader::named_ior(text)) return *value;
  doc_.fail(node, "unknown index of refraction '" + text + "'");
}

void BsdfReader::conserve_energy(Properties& props, pugi::xml_node node,
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

MaterialDesc BsdfReader::nested(pugi::xml_node node, Properties& props,
                                std::vector<pugi::xml_node>* textures) {
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

void BsdfReader::no_children(pugi::xml_node node, Properties& props) {
  for (pugi::xml_node child : props.objects())
    doc_.warn(child, "unsupported element <" + std::string(child.name()) + "> inside " +
                         doc_.describe(node) + " ignored");
}

MaterialDesc BsdfReader::build(const std::string& type, pugi::xml_node node, Properties& props) {
  // The wrappers and the weighted sums: their nested BSDFs, changed or combined
  // (mitsuba_bsdf_combining.cpp; the coatings in mitsuba_bsdf_plastic_coating.cpp).
  if (type == "twosided") return two_sided(node, props);
  if (type == "mask") return mask(node, props);
  if (type == "bumpmap") return bump_map(node, props);
  if (type == "coating" || type == "roughcoating") return coating(type, node, props);
  if (type == "normalmap") return normal_map(node, props);
  if (type == "mixturebsdf") return MaterialDesc("", mixture(node, props));
  if (type == "blendbsdf") return MaterialDesc("", blend(node, props));
  no_children(node, props);
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
  BsdfPtr bsdf;
  if (type == "diffuse")
    bsdf = diffuse(node, props);
  else if (type == "roughdiffuse")
    bsdf = rough_diffuse(node, props);
  else if (type == "difftrans")
    bsdf = diffuse_transmitter(node, props);
  else if (type == "phong")
    bsdf = phong(node, props);
  else if (type == "ward")
    bsdf = ward(node, props);
  else if (type == "dielectric" || type == "thindielectric")
    bsdf = dielectric(type, node, props);
  else if (type == "roughdielectric")
    bsdf = rough_dielectric(node, props);
  else if (type == "conductor")
    bsdf = conductor(node, props);
  else if (type == "roughconductor")
    bsdf = rough_conductor(node, props);
  else if (type == "plastic" || type == "roughplastic")
    bsdf = plastic(type, node, props);
  else if (type == "principled" && doc_.mitsuba3())
    bsdf = principled(node, props);
  else
    bsdf = unsupported(type, node, props);
  return MaterialDesc("", bsdf);
}

MaterialDesc read_bsdf(const Document& doc, pugi::xml_node node, NamedObjects& named,
                       std::vector<std::string>&) {
  return BsdfReader(doc, named).read(node);
}

}  // namespace emlt::mitsuba
