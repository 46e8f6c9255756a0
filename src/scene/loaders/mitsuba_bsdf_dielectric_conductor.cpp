// Mitsuba 0.6's dielectrics and conductors, smooth and rough: dielectric, thindielectric,
// roughdielectric, conductor and roughconductor, with their IORs (numbers or named
// materials) and specular tints.
#include <string>
#include <utility>

#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/materials.h"
#include "src/scene/loaders/mitsuba_bsdf_reader.h"

namespace emlt::mitsuba {

std::pair<TexturePtr, TexturePtr> BsdfReader::specular_tints(Properties& props,
                                                             pugi::xml_node node) {
  TexturePtr reflectance = texture(props, "specularReflectance", Rgb(1.0f));
  TexturePtr transmittance = texture(props, "specularTransmittance", Rgb(1.0f));
  conserve_energy(props, node, {&reflectance});
  conserve_energy(props, node, {&transmittance});
  return {reflectance, transmittance};
}

void BsdfReader::conductor_ior(Properties& props, pugi::xml_node node, Rgb* eta, Rgb* k) {
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

BsdfPtr BsdfReader::dielectric(const std::string& type, pugi::xml_node node, Properties& props) {
  const float int_ior = ior(props, "intIOR", 1.5046f, node);
  const float ext_ior = ior(props, "extIOR", 1.000277f, node);
  auto [reflectance, transmittance] = specular_tints(props, node);
  return type == "dielectric" ? make_dielectric(int_ior, ext_ior, reflectance, transmittance)
                              : make_thin_dielectric(int_ior, ext_ior, reflectance, transmittance);
}

BsdfPtr BsdfReader::rough_dielectric(pugi::xml_node node, Properties& props) {
  const MicrofacetType dist = distribution(props, node);
  const Roughness a = roughness(props, node);
  const float int_ior = ior(props, "intIOR", 1.5046f, node);
  const float ext_ior = ior(props, "extIOR", 1.000277f, node);
  auto [reflectance, transmittance] = specular_tints(props, node);
  return make_rough_dielectric(a.u, int_ior, ext_ior, dist, reflectance, transmittance, a.v);
}

BsdfPtr BsdfReader::conductor(pugi::xml_node node, Properties& props) {
  Rgb eta, k;
  conductor_ior(props, node, &eta, &k);
  TexturePtr specular = texture(props, "specularReflectance", Rgb(1.0f));
  conserve_energy(props, node, {&specular});
  return make_conductor(eta, k, specular);
}

BsdfPtr BsdfReader::rough_conductor(pugi::xml_node node, Properties& props) {
  const MicrofacetType dist = distribution(props, node);
  const Roughness a = roughness(props, node);
  Rgb eta, k;
  conductor_ior(props, node, &eta, &k);
  TexturePtr specular = texture(props, "specularReflectance", Rgb(1.0f));
  conserve_energy(props, node, {&specular});
  return make_rough_conductor(a.u, eta, k, specular, dist, a.v);
}

}  // namespace emlt::mitsuba
