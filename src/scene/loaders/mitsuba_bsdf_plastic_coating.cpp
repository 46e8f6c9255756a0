// Mitsuba 0.6's dielectric layers over a base: plastic and roughplastic (over a diffuse),
// coating and roughcoating (over a nested BSDF), each in Mitsuba's own model.
#include <string>

#include "emlt/scene/materials.h"
#include "src/scene/loaders/mitsuba_bsdf_reader.h"

namespace emlt::mitsuba {

BsdfPtr BsdfReader::plastic(const std::string& type, pugi::xml_node node, Properties& props) {
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

MaterialDesc BsdfReader::coating(const std::string& type, pugi::xml_node node, Properties& props) {
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

}  // namespace emlt::mitsuba
