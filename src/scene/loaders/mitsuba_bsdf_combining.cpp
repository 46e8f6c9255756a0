// Mitsuba 0.6's BSDFs that wrap or combine nested ones: twosided, mask (the material's
// opacity), bumpmap (its bump texture), normalmap (a wrapper that tilts the frame it sees),
// and the weighted sums mixturebsdf and blendbsdf.
#include <string>
#include <vector>

#include "emlt/scene/materials.h"
#include "src/scene/loaders/mitsuba_bsdf_reader.h"

namespace emlt::mitsuba {

MaterialDesc BsdfReader::two_sided(pugi::xml_node node, Properties& props) {
  // Every Mitsuba BSDF reads ensureEnergyConservation; this wrapper has nothing to scale.
  props.get_boolean("ensureEnergyConservation", true);
  MaterialDesc inner = nested(node, props);
  if (inner.bsdf->lobes() & kLobeTransmission) {
    if (doc_.mitsuba3())  // allow_transmission aside, Mitsuba 3 refuses it
      doc_.warn(node, "<twosided> around a transmissive BSDF is refused by Mitsuba 3; left out");
    else
      doc_.warn(node, "<twosided> around a transmissive BSDF has no effect; left out",
                Document::Warning::Note);
    return inner;
  }
  inner.bsdf = make_two_sided(inner.bsdf);
  return inner;
}

MaterialDesc BsdfReader::mask(pugi::xml_node node, Properties& props) {
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

MaterialDesc BsdfReader::bump_map(pugi::xml_node node, Properties& props) {
  // Every Mitsuba BSDF reads ensureEnergyConservation; this wrapper has nothing to scale.
  props.get_boolean("ensureEnergyConservation", true);
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

TexturePtr BsdfReader::mitsuba3_bump_height(pugi::xml_node node, Properties& props,
                                            TexturePtr height) {
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

MaterialDesc BsdfReader::normal_map(pugi::xml_node node, Properties& props) {
  // Every Mitsuba BSDF reads ensureEnergyConservation; this wrapper has nothing to scale.
  props.get_boolean("ensureEnergyConservation", true);
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

std::vector<BsdfPtr> BsdfReader::parts(pugi::xml_node node, Properties& props) {
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

BsdfPtr BsdfReader::mixture(pugi::xml_node node, Properties& props) {
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

BsdfPtr BsdfReader::blend(pugi::xml_node node, Properties& props) {
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

}  // namespace emlt::mitsuba
