// Mitsuba 0.6's diffuse and classic analytic BSDFs: diffuse, roughdiffuse (Oren-Nayar),
// difftrans, phong and ward; and what stands in for a BSDF emlt lacks (Mitsuba 3's
// principled, an unknown type).
#include <cctype>
#include <optional>
#include <string>
#include <utility>

#include "emlt/scene/materials.h"
#include "src/scene/loaders/mitsuba_bsdf_reader.h"

namespace emlt::mitsuba {

BsdfPtr BsdfReader::diffuse(pugi::xml_node node, Properties& props) {
  TexturePtr reflectance = texture(props, "reflectance", Rgb(0.5f));
  conserve_energy(props, node, {&reflectance});
  return make_lambertian(reflectance);
}

BsdfPtr BsdfReader::rough_diffuse(pugi::xml_node node, Properties& props) {
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

BsdfPtr BsdfReader::diffuse_transmitter(pugi::xml_node node, Properties& props) {
  // Mitsuba reads `diffuseTransmittance` too, when `transmittance` is not given.
  const char* name = props.has("transmittance") || !props.has("diffuseTransmittance")
                         ? "transmittance"
                         : "diffuseTransmittance";
  TexturePtr transmittance = texture(props, name, Rgb(0.5f));
  conserve_energy(props, node, {&transmittance});
  return make_diffuse_transmitter(transmittance);
}

BsdfPtr BsdfReader::phong(pugi::xml_node node, Properties& props) {
  TexturePtr exponent = texture(props, "exponent", Rgb(30.0f));
  if (auto c = exponent->constant(); c && !((c->x + c->y + c->z) >= 0.0f))
    doc_.fail(props.node_of("exponent"), "'exponent' of a phong must not be negative");
  TexturePtr specular = texture(props, "specularReflectance", Rgb(0.2f));
  TexturePtr diffuse = texture(props, "diffuseReflectance", Rgb(0.5f));
  conserve_energy(props, node, {&specular, &diffuse});
  return make_phong(exponent, specular, diffuse);
}

BsdfPtr BsdfReader::ward(pugi::xml_node node, Properties& props) {
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
      doc_.fail(props.node_of(which), std::string("'") + which + "' of a ward must be positive");
  TexturePtr specular = texture(props, "specularReflectance", Rgb(0.2f));
  TexturePtr diffuse = texture(props, "diffuseReflectance", Rgb(0.5f));
  conserve_energy(props, node, {&specular, &diffuse});
  return make_ward(*variant, alpha_u, alpha_v, specular, diffuse);
}

BsdfPtr BsdfReader::principled(pugi::xml_node node, Properties& props) {
  // Disney's diffuse lobe is not Lambertian (retro-reflection, sheen) and its specular
  // lobe is not any one BSDF here: no parameter set of it maps exactly.
  doc_.warn(node,
            "<bsdf type=\"principled\"> is not supported; rendered as a diffuse of its "
            "base_color (its other parameters ignored)");
  TexturePtr base = texture(props, "base_color", Rgb(0.5f));
  props.ignore_rest();  // one item for the whole BSDF
  return make_lambertian(base);
}

BsdfPtr BsdfReader::unsupported(const std::string& type, pugi::xml_node node, Properties& props) {
  doc_.warn(node, "unsupported BSDF type '" + type + "'; using a diffuse of reflectance 0.5");
  props.ignore({"specularReflectance", "exponent", "alpha", "alphaU", "alphaV"});
  for (const char* name : {"reflectance", "diffuseReflectance"})
    if (props.has(name)) return make_lambertian(texture(props, name, Rgb(0.5f)));
  return make_lambertian(Rgb(0.5f));
}

}  // namespace emlt::mitsuba
