// Thin dielectric slab (Mitsuba's `thindielectric`): two parallel interfaces so close
// that light leaves where it entered. Summing the bounces inside the slab gives the
// reflectance R' = R + T^2 R / (1 - R^2) (T = 1 - R), and the transmitted light continues
// in its original direction, so no refraction and no radiance compression. Both sides.
#include "emlt/scene/materials.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/texture_param.h"

namespace emlt {
namespace {

class ThinDielectric final : public Bsdf {
 public:
  ThinDielectric(float eta, TexturePtr reflectance, TexturePtr transmittance)
      : eta_(eta), reflectance_(std::move(reflectance)), transmittance_(std::move(transmittance)) {}

  Rgb eval(const BsdfContext&, const Vec3&, const Vec3&) const override { return Rgb(0.0f); }
  float pdf(const BsdfContext&, const Vec3&, const Vec3&) const override { return 0.0f; }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2&) const override {
    if (wo.z == 0.0f) return std::nullopt;
    const float slab_reflectance = reflectance(std::abs(wo.z));
    BsdfSample s;
    if (u_lobe < slab_reflectance) {
      s.wi = Vec3(-wo.x, -wo.y, wo.z);
      s.pdf = slab_reflectance;
      s.weight = reflectance_.at(ctx);
      s.lobe = kLobeSpecular | kLobeReflection;
    } else {
      s.wi = -wo;
      s.pdf = 1.0f - slab_reflectance;
      s.weight = transmittance_.at(ctx);
      s.lobe = kLobeSpecular | kLobeTransmission;
    }
    if (!(s.pdf > 0.0f)) return std::nullopt;
    s.value = s.weight * (s.pdf / std::abs(s.wi.z));
    s.pdf_reverse = s.pdf;  // same |cos| from either direction
    s.eta = 1.0f;
    return s;
  }

  uint32_t lobes() const override {
    return kLobeSpecular | kLobeReflection | kLobeTransmission;
  }
  std::string name() const override { return "thin_dielectric"; }

  float reflectance(float cos_theta) const {
    const float r = fresnel_dielectric(cos_theta, eta_);
    if (r >= 1.0f) return 1.0f;
    const float t = 1.0f - r;
    return r + t * t * r / (1.0f - r * r);
  }

 private:
  float eta_;
  TextureParam reflectance_, transmittance_;  // Mitsuba's specular tints, numbers or textures
};

}  // namespace

BsdfPtr make_thin_dielectric(float int_ior, float ext_ior, TexturePtr specular_reflectance,
                             TexturePtr specular_transmittance) {
  return std::make_shared<ThinDielectric>(int_ior / ext_ior, std::move(specular_reflectance),
                                          std::move(specular_transmittance));
}

BsdfPtr make_thin_dielectric(float int_ior, float ext_ior, const Rgb& specular_reflectance,
                             const Rgb& specular_transmittance) {
  return make_thin_dielectric(int_ior, ext_ior, make_constant_texture(specular_reflectance),
                              make_constant_texture(specular_transmittance));
}

}  // namespace emlt
