// Rough conductor: GGX microfacets (height-correlated Smith masking-shadowing) with the
// exact conductor Fresnel term per RGB channel; visible-normal sampling. One-sided.
#include "emlt/scene/materials.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/microfacet.h"

namespace emlt {
namespace {

class RoughConductor final : public Bsdf {
 public:
  RoughConductor(float alpha, const Rgb& eta, const Rgb& k, const Rgb& reflectance)
      : ggx_(alpha), eta_(eta), k_(k), reflectance_(reflectance) {}

  // f = R F(wi.h) D(h) G2(wo, wi) / (4 cos_o cos_i)
  Rgb eval(const BsdfContext&, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Rgb(0.0f);
    const Vec3 h = reflection_half_vector(wo, wi);
    const float d = ggx_.D(h);
    if (d == 0.0f) return Rgb(0.0f);
    const Rgb fresnel = fresnel_conductor(glm::dot(wi, h), eta_, k_);
    return reflectance_ * fresnel * (d * ggx_.G2(wo, wi) / (4.0f * wo.z * wi.z));
  }

  float pdf(const BsdfContext&, const Vec3& wo, const Vec3& wi) const override {
    return ggx_.reflection_pdf(wo, wi);
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float,
                                   const Vec2& u) const override {
    if (wo.z <= 0.0f) return std::nullopt;
    const Vec3 m = ggx_.sample_visible_normal(wo, u);
    BsdfSample s;
    s.wi = reflect_about(wo, m);
    if (s.wi.z <= 0.0f) return std::nullopt;  // reflected into the surface: lost energy
    s.pdf = pdf(ctx, wo, s.wi);
    if (s.pdf <= 0.0f || !std::isfinite(s.pdf)) return std::nullopt;
    s.value = eval(ctx, wo, s.wi);
    // Simplifies to R F G2 / G1(wo); computed from value/pdf so that the two always agree.
    s.weight = s.value * (s.wi.z / s.pdf);
    if (!is_finite(s.weight)) return std::nullopt;
    s.pdf_reverse = ggx_.reflection_pdf(s.wi, wo);
    s.lobe = kLobeGlossy | kLobeReflection;
    return s;
  }

  uint32_t lobes() const override { return kLobeGlossy | kLobeReflection; }
  std::string name() const override { return "rough_conductor"; }

 private:
  GgxDistribution ggx_;
  Rgb eta_, k_, reflectance_;
};

}  // namespace

BsdfPtr make_rough_conductor(float alpha, const Rgb& eta, const Rgb& k,
                             const Rgb& specular_reflectance) {
  return std::make_shared<RoughConductor>(alpha, glm::max(eta, Rgb(0.0f)), glm::max(k, Rgb(0.0f)),
                                          glm::max(specular_reflectance, Rgb(0.0f)));
}

}  // namespace emlt
