// Rough dielectric interface (Walter et al. 2007, "Microfacet models for refraction
// through rough surfaces"), with the generalised half vector m ~ eta' wi + wo for both
// reflection and refraction, visible-normal (GGX) or full-distribution (Beckmann, Phong)
// sampling, and the reflection/refraction choice made with the microfacet's Fresnel
// reflectance. Works from both sides; eta' is always n(wi side) / n(wo side). As Mitsuba
// 0.6's roughdielectric: anisotropic roughness, separable Smith masking-shadowing.
#include <utility>

#include "emlt/scene/materials.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/microfacet.h"
#include "src/scene/materials/texture_param.h"

namespace emlt {
namespace {

class RoughDielectric final : public Bsdf {
 public:
  RoughDielectric(TexturePtr alpha_u, TexturePtr alpha_v, MicrofacetType type, float eta,
                  TexturePtr reflectance, TexturePtr transmittance)
      : alpha_u_(std::move(alpha_u)),
        alpha_v_(alpha_v ? std::make_optional<TextureParam>(std::move(alpha_v)) : std::nullopt),
        type_(type),
        eta_(eta),
        reflectance_(std::move(reflectance)),
        transmittance_(std::move(transmittance)) {}

  // With G = G1(wo, m) G1(wi, m):
  // Reflection: f = Ks F D G / (4 |cos_o cos_i|).
  // Refraction: f = Kt (1 - F) D G |wi.m wo.m| / (|cos_o cos_i| (wi.m + wo.m / eta')^2),
  // divided by eta'^2 for radiance (the compression of the solid angle; importance is not
  // compressed, which makes the importance BSDF the radiance one with arguments swapped).
  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    const Geometry g = geometry(wo, wi);
    if (!g.valid) return Rgb(0.0f);
    const MicrofacetDistribution dist = distribution(ctx);
    const float d = dist.D(g.m);
    if (d == 0.0f) return Rgb(0.0f);
    const float fresnel = fresnel_dielectric(glm::dot(wo, g.m), eta_);
    const float masking = dist.G(wo, wi, g.m);
    const float cos_product = std::abs(wo.z * wi.z);
    if (g.reflection) return reflectance_.at(ctx) * (fresnel * d * masking / (4.0f * cos_product));
    const float wi_m = glm::dot(wi, g.m), wo_m = glm::dot(wo, g.m);
    const float denom = square(wi_m + wo_m / g.eta_prime);
    float f = (1.0f - fresnel) * d * masking * std::abs(wi_m * wo_m) / (cos_product * denom);
    if (ctx.mode == TransportMode::Radiance) f /= square(g.eta_prime);
    return transmittance_.at(ctx) * f;
  }

  float pdf(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    const Geometry g = geometry(wo, wi);
    if (!g.valid) return 0.0f;
    const MicrofacetDistribution dist = distribution(ctx);
    const float wo_m = glm::dot(wo, g.m);
    const float fresnel = fresnel_dielectric(wo_m, eta_);
    const float normal_density = dist.normal_pdf(wo, g.m);
    if (g.reflection) return fresnel * normal_density / (4.0f * std::abs(wo_m));
    const float wi_m = glm::dot(wi, g.m);
    const float jacobian = std::abs(wi_m) / square(wi_m + wo_m / g.eta_prime);
    return (1.0f - fresnel) * normal_density * jacobian;
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2& u) const override {
    if (wo.z == 0.0f) return std::nullopt;
    const Vec3 m = distribution(ctx).sample_normal(wo, u);
    const float wo_m = glm::dot(wo, m);
    if (wo_m * wo.z <= 0.0f) return std::nullopt;  // back-facing microfacet
    float cos_t = 0.0f;
    const float fresnel = fresnel_dielectric(wo_m, eta_, &cos_t);
    BsdfSample s;
    if (u_lobe < fresnel) {
      s.wi = reflect_about(wo, m);
      if (s.wi.z * wo.z <= 0.0f) return std::nullopt;
      s.lobe = kLobeGlossy | kLobeReflection;
      s.eta = 1.0f;
    } else {
      // Snell's law about m; cos_t is signed (on the far side of m from wo).
      const float eta_prime = wo.z > 0.0f ? eta_ : 1.0f / eta_;
      s.wi = glm::normalize(-wo / eta_prime + (wo_m / eta_prime + cos_t) * m);
      if (s.wi.z * wo.z >= 0.0f) return std::nullopt;
      s.lobe = kLobeGlossy | kLobeTransmission;
      s.eta = eta_prime;
    }
    s.pdf = pdf(ctx, wo, s.wi);
    if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
    s.value = eval(ctx, wo, s.wi);
    s.weight = s.value * (std::abs(s.wi.z) / s.pdf);
    if (!is_finite(s.weight)) return std::nullopt;
    s.pdf_reverse = pdf(ctx, s.wi, wo);
    return s;
  }

  uint32_t lobes() const override {
    return kLobeGlossy | kLobeReflection | kLobeTransmission;
  }
  bool is_anisotropic() const override { return alpha_v_.has_value(); }
  // Mitsuba's two components (reflection and refraction) share the roughness.
  RoughComponents rough_components(const BsdfContext& ctx) const override {
    RoughComponents r;
    r.count = 1;
    r.alpha[0] = alpha_v_ ? std::numeric_limits<float>::infinity() : alpha_u_.average_at(ctx);
    r.eta = eta_;
    return r;
  }
  std::string name() const override {
    return type_ == MicrofacetType::Ggx        ? "rough_dielectric"
           : type_ == MicrofacetType::Beckmann ? "rough_dielectric_beckmann"
                                               : "rough_dielectric_phong";
  }

 private:
  struct Geometry {
    bool valid = false, reflection = false;
    Vec3 m{0.0f};  // generalised half vector, m.z > 0
    float eta_prime = 1.0f;
  };

  Geometry geometry(const Vec3& wo, const Vec3& wi) const {
    Geometry g;
    if (wo.z == 0.0f || wi.z == 0.0f) return g;
    g.reflection = wo.z * wi.z > 0.0f;
    g.eta_prime = g.reflection ? 1.0f : (wo.z > 0.0f ? eta_ : 1.0f / eta_);
    Vec3 m = wi * g.eta_prime + wo;
    const float length2 = glm::dot(m, m);
    if (!(length2 > 0.0f)) return g;
    m /= std::sqrt(length2);
    if (m.z < 0.0f) m = -m;
    // Both directions must see the microfacet from their own side of the surface.
    if (glm::dot(m, wi) * wi.z <= 0.0f || glm::dot(m, wo) * wo.z <= 0.0f) return g;
    g.m = m;
    g.valid = true;
    return g;
  }

  MicrofacetDistribution distribution(const BsdfContext& ctx) const {
    const float alpha_u = alpha_u_.average_at(ctx);
    return MicrofacetDistribution(type_, alpha_u, alpha_v_ ? alpha_v_->average_at(ctx) : alpha_u);
  }

  TextureParam alpha_u_;
  std::optional<TextureParam> alpha_v_;  // absent: isotropic
  MicrofacetType type_;
  float eta_;  // n_inside / n_outside
  TextureParam reflectance_, transmittance_;  // Mitsuba's specular tints, numbers or textures
};

}  // namespace

BsdfPtr make_rough_dielectric(TexturePtr alpha, float int_ior, float ext_ior,
                              MicrofacetType distribution, TexturePtr specular_reflectance,
                              TexturePtr specular_transmittance, TexturePtr alpha_v) {
  return std::make_shared<RoughDielectric>(std::move(alpha), std::move(alpha_v), distribution,
                                           int_ior / ext_ior, std::move(specular_reflectance),
                                           std::move(specular_transmittance));
}

BsdfPtr make_rough_dielectric(TexturePtr alpha, float int_ior, float ext_ior,
                              MicrofacetType distribution, const Rgb& specular_reflectance,
                              const Rgb& specular_transmittance, TexturePtr alpha_v) {
  return make_rough_dielectric(std::move(alpha), int_ior, ext_ior, distribution,
                               make_constant_texture(specular_reflectance),
                               make_constant_texture(specular_transmittance), std::move(alpha_v));
}

}  // namespace emlt
