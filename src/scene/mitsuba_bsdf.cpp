// Mitsuba 0.6 <bsdf> elements mapped onto the built-in BSDFs. Mitsuba's defaults are kept
// (diffuse reflectance 0.5, intIOR bk7 for dielectrics, polypropylene for plastics, Cu
// conductors, alpha 0.1) so that a scene renders like it does in Mitsuba.
#include "emlt/core/error.h"
#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/materials.h"
#include "src/scene/loader_common.h"
#include "src/scene/mitsuba_parser.h"

namespace emlt::mitsuba {

namespace {

class BsdfReader {
 public:
  BsdfReader(const Document& doc, std::map<std::string, BsdfPtr>& named,
             std::vector<std::string>& warnings)
      : doc_(doc), named_(named), warnings_(warnings) {}

  BsdfPtr read(pugi::xml_node node) {
    if (std::string(node.name()) == "ref") {
      const std::string id = doc_.attribute(node, "id");
      auto it = named_.find(id);
      if (it == named_.end()) doc_.fail(node, "unknown reference id '" + id + "'");
      return it->second;
    }
    const std::string type = doc_.attribute(node, "type");
    Properties props(doc_, node);
    BsdfPtr bsdf = build(type, node, props);
    props.warn_unused();
    if (doc_.has_attribute(node, "id")) named_[doc_.attribute(node, "id")] = bsdf;
    return bsdf;
  }

 private:
  float ior(Properties& props, const char* name, float fallback, pugi::xml_node node) {
    if (!props.has(name)) return fallback;
    // Mitsuba accepts a number (<float>) or a material name (<string>) for an IOR.
    if (props.kind_of(name) != "string") return props.get_float(name, fallback);
    const std::string text = props.get_string(name, "");
    if (auto value = loader::named_ior(text)) return *value;
    doc_.fail(node, "unknown index of refraction '" + text + "'");
  }

  // Mitsuba's conductor parameters, divided by the exterior IOR like Mitsuba does.
  void conductor_ior(Properties& props, pugi::xml_node node, Rgb* eta, Rgb* k) {
    if (props.has("eta") || props.has("k")) {
      *eta = props.get_color("eta", Rgb(0.0f));
      *k = props.get_color("k", Rgb(1.0f));
      if (props.has("material")) doc_.warn(node, "'material' ignored because eta/k are given");
      props.ignore({"material"});
    } else {
      const std::string material = props.get_string("material", "Cu");
      if (!conductor_preset(material, eta, k))
        doc_.fail(node, "unknown conductor material '" + material + "'");
    }
    const float ext_eta = ior(props, "extEta", 1.0f, node);
    *eta /= ext_eta;
    *k /= ext_eta;
  }

  float alpha(Properties& props, pugi::xml_node node) {
    const std::string distribution = props.get_string("distribution", "beckmann");
    if (distribution != "ggx")
      doc_.warn(node, "microfacet distribution '" + distribution + "'" +
                          (props.has("distribution") ? "" : " (Mitsuba's default)") +
                          " is not supported; using GGX with the same alpha");
    float a = props.get_float("alpha", 0.1f);
    if (props.has("alphaU") || props.has("alphaV")) {
      const float u = props.get_float("alphaU", a), v = props.get_float("alphaV", a);
      if (u != v)
        doc_.warn(node, "anisotropic roughness approximated by the mean of alphaU and alphaV");
      a = 0.5f * (u + v);
    }
    if (!(a > 0.0f)) doc_.fail(node, "alpha must be positive");
    return a;
  }

  BsdfPtr nested(pugi::xml_node node, Properties& props) {
    pugi::xml_node inner;
    for (pugi::xml_node child : props.objects()) {
      const std::string kind = child.name();
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

  BsdfPtr build(const std::string& type, pugi::xml_node node, Properties& props) {
    if (type == "twosided") {
      BsdfPtr inner = nested(node, props);
      if (inner->lobes() & kLobeTransmission) {
        doc_.warn(node, "<twosided> around a transmissive BSDF has no effect; left out");
        return inner;
      }
      return make_two_sided(inner);
    }
    if (type == "mask" || type == "bumpmap" || type == "normalmap" || type == "coating") {
      doc_.warn(node, "<bsdf type=\"" + type + "\"> is not supported; using its nested BSDF alone");
      props.ignore({"opacity", "thickness", "intIOR", "extIOR", "sigmaA", "specularReflectance"});
      return nested(node, props);
    }
    no_children(node, props);
    if (type == "diffuse" || type == "roughdiffuse") {
      if (type == "roughdiffuse") {
        doc_.warn(node, "roughdiffuse approximated by a Lambertian diffuse");
        props.ignore({"alpha", "useFastApprox"});
      }
      return make_lambertian(props.get_color("reflectance", Rgb(0.5f)));
    }
    if (type == "dielectric" || type == "roughdielectric" || type == "thindielectric") {
      if (type != "dielectric") {
        doc_.warn(node, type + " approximated by a smooth dielectric");
        props.ignore({"alpha", "alphaU", "alphaV", "distribution"});
      }
      const float int_ior = ior(props, "intIOR", 1.5046f, node);
      const float ext_ior = ior(props, "extIOR", 1.000277f, node);
      return make_dielectric(int_ior, ext_ior, props.get_color("specularReflectance", Rgb(1.0f)),
                             props.get_color("specularTransmittance", Rgb(1.0f)));
    }
    if (type == "conductor") {
      Rgb eta, k;
      conductor_ior(props, node, &eta, &k);
      const Rgb specular = props.get_color("specularReflectance", Rgb(1.0f));
      return loader::make_smooth_conductor(
          eta, k, specular, doc_.path() + ": line " + std::to_string(doc_.line(node)), warnings_);
    }
    if (type == "roughconductor") {
      const float a = alpha(props, node);
      Rgb eta, k;
      conductor_ior(props, node, &eta, &k);
      return make_rough_conductor(a, eta, k, props.get_color("specularReflectance", Rgb(1.0f)));
    }
    if (type == "plastic" || type == "roughplastic") {
      const float a = type == "plastic" ? 0.0f : alpha(props, node);
      if (props.get_boolean("nonlinear", false))
        doc_.warn(node, "nonlinear plastic is not supported; rendered as linear");
      const float int_ior = ior(props, "intIOR", 1.49f, node);
      const float ext_ior = ior(props, "extIOR", 1.000277f, node);
      return make_rough_plastic(a, props.get_color("diffuseReflectance", Rgb(0.5f)),
                                props.get_color("specularReflectance", Rgb(1.0f)), int_ior,
                                ext_ior);
    }
    doc_.warn(node, "unsupported BSDF type '" + type + "'; using a diffuse of reflectance 0.5");
    for (const char* name : {"reflectance", "diffuseReflectance"})
      if (props.has(name)) {
        const Rgb reflectance = props.get_color(name, Rgb(0.5f));
        props.ignore({"specularReflectance", "exponent", "alpha", "alphaU", "alphaV"});
        return make_lambertian(reflectance);
      }
    props.ignore({"specularReflectance", "exponent", "alpha", "alphaU", "alphaV"});
    return make_lambertian(Rgb(0.5f));
  }

  const Document& doc_;
  std::map<std::string, BsdfPtr>& named_;
  std::vector<std::string>& warnings_;
};

}  // namespace

BsdfPtr read_bsdf(const Document& doc, pugi::xml_node node, std::map<std::string, BsdfPtr>& named,
                  std::vector<std::string>& warnings) {
  return BsdfReader(doc, named, warnings).read(node);
}

}  // namespace emlt::mitsuba
