// Conductors: the rough one is a microfacet BRDF (Mitsuba 0.6's roughconductor: GGX,
// Beckmann or Phong, isotropic or anisotropic, separable Smith masking-shadowing) with the
// exact conductor Fresnel term per RGB channel; the
// smooth one a delta reflection weighted by the same Fresnel term. Both one-sided; the
// roughness and the specular tint may be textures.
#include <utility>

#include "emlt/scene/materials.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/microfacet.h"
#include "src/scene/materials/texture_param.h"

namespace emlt {
namespace {

class RoughConductor final : public Bsdf {
 public:
  RoughConductor(TexturePtr alpha_u, TexturePtr alpha_v, MicrofacetType type, const Rgb& eta,
                 const Rgb& k, TexturePtr reflectance)
      : alpha_u_(std::move(alpha_u)),
        alpha_v_(alpha_v ? std::make_optional<TextureParam>(std::move(alpha_v)) : std::nullopt),
        type_(type), eta_(eta), k_(k), reflectance_(std::move(reflectance)) {}

  // f = R F(wi.h) D(h) G1(wo, h) G1(wi, h) / (4 cos_o cos_i)
  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Rgb(0.0f);
    const MicrofacetDistribution dist = distribution(ctx);
    const Vec3 h = reflection_half_vector(wo, wi);
    const float d = dist.D(h);
    if (d == 0.0f) return Rgb(0.0f);
    const Rgb fresnel = fresnel_conductor(glm::dot(wi, h), eta_, k_);
    return reflectance_.at(ctx) * fresnel * (d * dist.G(wo, wi, h) / (4.0f * wo.z * wi.z));
  }

  float pdf(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    return distribution(ctx).reflection_pdf(wo, wi);
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float,
                                   const Vec2& u) const override {
    if (wo.z <= 0.0f) return std::nullopt;
    const Vec3 m = distribution(ctx).sample_normal(wo, u);
    if (glm::dot(wo, m) <= 0.0f) return std::nullopt;  // back-facing (full-distribution sampling)
    BsdfSample s;
    s.wi = reflect_about(wo, m);
    if (s.wi.z <= 0.0f) return std::nullopt;  // reflected into the surface: lost energy
    s.pdf = pdf(ctx, wo, s.wi);
    if (s.pdf <= 0.0f || !std::isfinite(s.pdf)) return std::nullopt;
    s.value = eval(ctx, wo, s.wi);
    // Computed from value/pdf so that the two always agree.
    s.weight = s.value * (s.wi.z / s.pdf);
    if (!is_finite(s.weight)) return std::nullopt;
    s.pdf_reverse = pdf(ctx, s.wi, wo);
    s.lobe = kLobeGlossy | kLobeReflection;
    return s;
  }

  uint32_t lobes() const override { return kLobeGlossy | kLobeReflection; }
  bool is_anisotropic() const override { return alpha_v_.has_value(); }
  RoughComponents rough_components(const BsdfContext& ctx) const override {
    RoughComponents r;
    r.count = 1;
    r.alpha[0] = alpha_v_ ? std::numeric_limits<float>::infinity() : alpha_u_.average_at(ctx);
    return r;
  }
  std::string name() const override {
    return type_ == MicrofacetType::Ggx        ? "rough_conductor"
           : type_ == MicrofacetType::Beckmann ? "rough_conductor_beckmann"
                                               : "rough_conductor_phong";
  }

 private:
  MicrofacetDistribution distribution(const BsdfContext& ctx) const {
    const float alpha_u = alpha_u_.average_at(ctx);
    return MicrofacetDistribution(type_, alpha_u, alpha_v_ ? alpha_v_->average_at(ctx) : alpha_u);
  }

  TextureParam alpha_u_;
  std::optional<TextureParam> alpha_v_;  // absent: isotropic
  MicrofacetType type_;
  Rgb eta_, k_;
  TextureParam reflectance_;
};

class SmoothConductor final : public Bsdf {
 public:
  SmoothConductor(const Rgb& eta, const Rgb& k, TexturePtr reflectance)
      : eta_(eta), k_(k), reflectance_(std::move(reflectance)) {}

  Rgb eval(const BsdfContext&, const Vec3&, const Vec3&) const override { return Rgb(0.0f); }
  float pdf(const BsdfContext&, const Vec3&, const Vec3&) const override { return 0.0f; }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float,
                                   const Vec2&) const override {
    if (wo.z <= 0.0f) return std::nullopt;
    BsdfSample s;
    s.wi = Vec3(-wo.x, -wo.y, wo.z);
    s.pdf = 1.0f;
    s.pdf_reverse = 1.0f;
    s.weight = reflectance_.at(ctx) * fresnel_conductor(wo.z, eta_, k_);
    s.value = s.weight / s.wi.z;
    s.lobe = kLobeSpecular | kLobeReflection;
    if (!is_finite(s.value)) return std::nullopt;
    return s;
  }

  uint32_t lobes() const override { return kLobeSpecular | kLobeReflection; }
  std::string name() const override { return "conductor"; }

 private:
  Rgb eta_, k_;
  TextureParam reflectance_;
};

}  // namespace

BsdfPtr make_rough_conductor(float alpha, const Rgb& eta, const Rgb& k,
                             const Rgb& specular_reflectance) {
  return make_rough_conductor(make_constant_texture(Rgb(alpha)), eta, k,
                              make_constant_texture(glm::max(specular_reflectance, Rgb(0.0f))));
}

BsdfPtr make_rough_conductor(TexturePtr alpha, const Rgb& eta, const Rgb& k,
                             TexturePtr specular_reflectance, MicrofacetType distribution,
                             TexturePtr alpha_v) {
  return std::make_shared<RoughConductor>(std::move(alpha), std::move(alpha_v), distribution,
                                          glm::max(eta, Rgb(0.0f)), glm::max(k, Rgb(0.0f)),
                                          std::move(specular_reflectance));
}

BsdfPtr make_conductor(const Rgb& eta, const Rgb& k, const Rgb& specular_reflectance) {
  return make_conductor(eta, k, make_constant_texture(glm::max(specular_reflectance, Rgb(0.0f))));
}

BsdfPtr make_conductor(const Rgb& eta, const Rgb& k, TexturePtr specular_reflectance) {
  return std::make_shared<SmoothConductor>(glm::max(eta, Rgb(0.0f)), glm::max(k, Rgb(0.0f)),
                                           std::move(specular_reflectance));
}

}  // namespace emlt
