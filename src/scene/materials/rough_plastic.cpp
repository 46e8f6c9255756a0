// Plastic: a diffuse base under a dielectric coating (after Mitsuba 0.6 `roughplastic` /
// `plastic`, nonlinear = false). The coating reflects through a GGX lobe (or a delta when
// alpha == 0); light refracted into the coating is scattered diffusely by the base, and
// the internal reflections off the coating are accounted for by the average internal
// Fresnel reflectance. One-sided.
#include "emlt/core/warp.h"
#include "emlt/scene/materials.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/microfacet.h"

namespace emlt {
namespace {

class RoughPlastic final : public Bsdf {
 public:
  RoughPlastic(float alpha, const Rgb& diffuse, const Rgb& specular, float eta)
      : smooth_(alpha <= 0.0f), ggx_(alpha), diffuse_(diffuse), specular_(specular), eta_(eta) {
    // With white base and coating the diffuse lobe then reflects exactly 1 - F(cos_o): the
    // fraction of light leaving the coating after any number of internal bounces.
    const float internal_reflectance = fresnel_diffuse_reflectance(1.0f / eta_);
    diffuse_scale_ = 1.0f / (eta_ * eta_ * glm::max(1.0f - internal_reflectance, 1e-6f));
    const float specular_albedo = (specular_.x + specular_.y + specular_.z) / 3.0f;
    const float diffuse_albedo = (diffuse_.x + diffuse_.y + diffuse_.z) / 3.0f;
    const float total = specular_albedo + diffuse_albedo;
    specular_weight_ = total > 0.0f ? specular_albedo / total : 0.5f;
  }

  Rgb eval(const BsdfContext&, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Rgb(0.0f);
    Rgb result = diffuse_value(wo, wi);
    if (!smooth_) {
      // Coating: f = Ks F(wo.h) D(h) G2 / (4 cos_o cos_i)
      const Vec3 h = reflection_half_vector(wo, wi);
      const float fresnel = fresnel_dielectric(glm::dot(wo, h), eta_);
      result += specular_ * (fresnel * ggx_.D(h) * ggx_.G2(wo, wi) / (4.0f * wo.z * wi.z));
    }
    return result;
  }

  // Mixture of the two lobes' densities; for a smooth coating only the diffuse part, since
  // the delta lobe has no density.
  float pdf(const BsdfContext&, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    const float p_specular = specular_probability(wo.z);
    float density = (1.0f - p_specular) * cosine_hemisphere_pdf(wi);
    if (!smooth_) density += p_specular * ggx_.reflection_pdf(wo, wi);
    return density;
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2& u) const override {
    if (wo.z <= 0.0f) return std::nullopt;
    const float p_specular = specular_probability(wo.z);
    BsdfSample s;
    if (smooth_ && u_lobe < p_specular) {
      s.wi = Vec3(-wo.x, -wo.y, wo.z);
      const float fresnel = fresnel_dielectric(wo.z, eta_);
      s.pdf = p_specular;
      s.pdf_reverse = p_specular;  // same cosine from wi, same choice
      s.value = specular_ * (fresnel / wo.z);
      s.weight = specular_ * (fresnel / p_specular);
      s.lobe = kLobeSpecular | kLobeReflection;
      if (!is_finite(s.value)) return std::nullopt;
      return s;
    }
    if (u_lobe < p_specular) {
      s.wi = reflect_about(wo, ggx_.sample_visible_normal(wo, u));
      s.lobe = kLobeGlossy | kLobeReflection;
    } else {
      s.wi = square_to_cosine_hemisphere(u);
      s.lobe = kLobeDiffuse | kLobeReflection;
    }
    if (s.wi.z <= 0.0f) return std::nullopt;
    s.pdf = pdf(ctx, wo, s.wi);
    if (s.pdf <= 0.0f || !std::isfinite(s.pdf)) return std::nullopt;
    s.value = eval(ctx, wo, s.wi);
    s.weight = s.value * (s.wi.z / s.pdf);
    if (!is_finite(s.weight)) return std::nullopt;
    s.pdf_reverse = pdf(ctx, s.wi, wo);
    return s;
  }

  uint32_t lobes() const override {
    return kLobeDiffuse | kLobeReflection | (smooth_ ? kLobeSpecular : kLobeGlossy);
  }
  std::string name() const override { return smooth_ ? "plastic" : "rough_plastic"; }

 private:
  // Base seen through the coating: Kd / pi * (1 - F(cos_i)) (1 - F(cos_o)) * diffuse_scale_.
  Rgb diffuse_value(const Vec3& wo, const Vec3& wi) const {
    const float transmit_in = 1.0f - fresnel_dielectric(wi.z, eta_);
    const float transmit_out = 1.0f - fresnel_dielectric(wo.z, eta_);
    return diffuse_ * (kInvPi * diffuse_scale_ * transmit_in * transmit_out);
  }

  // Probability of sampling the coating lobe: its Fresnel-weighted albedo estimate against
  // the base's, so that bright coatings at grazing angles get most samples.
  float specular_probability(float cos_o) const {
    const float fresnel = fresnel_dielectric(cos_o, eta_);
    const float specular = fresnel * specular_weight_;
    const float diffuse = (1.0f - fresnel) * (1.0f - specular_weight_);
    return specular + diffuse > 0.0f ? specular / (specular + diffuse) : specular_weight_;
  }

  bool smooth_;
  GgxDistribution ggx_;
  Rgb diffuse_, specular_;
  float eta_;  // n_inside / n_outside of the coating
  float diffuse_scale_ = 1.0f;
  float specular_weight_ = 0.5f;
};

}  // namespace

BsdfPtr make_rough_plastic(float alpha, const Rgb& diffuse_reflectance,
                           const Rgb& specular_reflectance, float int_ior, float ext_ior) {
  return std::make_shared<RoughPlastic>(alpha, glm::max(diffuse_reflectance, Rgb(0.0f)),
                                        glm::max(specular_reflectance, Rgb(0.0f)),
                                        int_ior / ext_ior);
}

}  // namespace emlt
