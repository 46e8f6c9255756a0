// Smooth dielectric interface: a reflection and a refraction delta lobe, chosen in
// proportion to the exact unpolarised Fresnel reflectance. Works from both sides.
#include "emlt/scene/materials.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/texture_param.h"

namespace emlt {
namespace {

class Dielectric final : public Bsdf {
 public:
  Dielectric(float eta, TexturePtr reflectance, TexturePtr transmittance)
      : eta_(eta), reflectance_(std::move(reflectance)), transmittance_(std::move(transmittance)) {}

  Rgb eval(const BsdfContext&, const Vec3&, const Vec3&) const override { return Rgb(0.0f); }
  float pdf(const BsdfContext&, const Vec3&, const Vec3&) const override { return 0.0f; }

  // Reflection is chosen with probability F, refraction with 1 - F, so the weight of
  // either is the tint alone (times the radiance compression for refraction). Fresnel
  // reflectance is symmetric across the interface (F(theta_i) seen from one side equals
  // F(theta_t) from the other), hence pdf_reverse == pdf for both lobes.
  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2&) const override {
    if (wo.z == 0.0f) return std::nullopt;
    float cos_t = 0.0f;
    const float fresnel = fresnel_dielectric(wo.z, eta_, &cos_t);
    BsdfSample s;
    if (u_lobe < fresnel) {
      s.wi = Vec3(-wo.x, -wo.y, wo.z);
      s.pdf = fresnel;
      const Rgb tint = reflectance_.at(ctx);
      s.value = tint * (fresnel / std::abs(s.wi.z));
      s.weight = tint;
      s.lobe = kLobeSpecular | kLobeReflection;
      s.eta = 1.0f;
    } else {
      // Relative IOR crossed along wi: inside over outside when entering.
      const float eta_rel = wo.z > 0.0f ? eta_ : 1.0f / eta_;
      s.wi = Vec3(-wo.x / eta_rel, -wo.y / eta_rel, cos_t);
      if (s.wi.z == 0.0f) return std::nullopt;
      s.wi = glm::normalize(s.wi);  // removes float drift; exact Snell's law has |wi| = 1
      s.pdf = 1.0f - fresnel;
      // Radiance is compressed by (n_wo / n_wi)^2 on refraction; importance is not.
      const float scale =
          ctx.mode == TransportMode::Radiance ? 1.0f / (eta_rel * eta_rel) : 1.0f;
      const Rgb tint = transmittance_.at(ctx);
      s.value = tint * (scale * (1.0f - fresnel) / std::abs(s.wi.z));
      s.weight = tint * scale;
      s.lobe = kLobeSpecular | kLobeTransmission;
      s.eta = eta_rel;
    }
    if (s.pdf <= 0.0f || !is_finite(s.value)) return std::nullopt;
    s.pdf_reverse = s.pdf;
    return s;
  }

  uint32_t lobes() const override {
    return kLobeSpecular | kLobeReflection | kLobeTransmission;
  }
  std::string name() const override { return "dielectric"; }

 private:
  float eta_;  // n_inside / n_outside
  TextureParam reflectance_, transmittance_;  // Mitsuba's specular tints, numbers or textures
};

}  // namespace

BsdfPtr make_dielectric(float int_ior, float ext_ior, TexturePtr specular_reflectance,
                        TexturePtr specular_transmittance) {
  return std::make_shared<Dielectric>(int_ior / ext_ior, std::move(specular_reflectance),
                                      std::move(specular_transmittance));
}

BsdfPtr make_dielectric(float int_ior, float ext_ior, const Rgb& specular_reflectance,
                        const Rgb& specular_transmittance) {
  return make_dielectric(int_ior, ext_ior, make_constant_texture(specular_reflectance),
                         make_constant_texture(specular_transmittance));
}

}  // namespace emlt
