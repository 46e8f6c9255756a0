// The microfacet parameters of Mitsuba 0.6's rough BSDFs (roughdielectric, roughconductor,
// roughplastic, roughcoating): the distribution and the roughness, alpha or alphaU/alphaV,
// read as Mitsuba reads and refuses them.
#include <cctype>
#include <string>

#include "emlt/scene/materials.h"
#include "src/scene/loaders/mitsuba_bsdf_reader.h"

namespace emlt::mitsuba {

MicrofacetType BsdfReader::distribution(Properties& props, pugi::xml_node node) {
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

BsdfReader::Roughness BsdfReader::roughness(Properties& props, pugi::xml_node node) {
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

TexturePtr BsdfReader::alpha(Properties& props, pugi::xml_node node) {
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

}  // namespace emlt::mitsuba
