// Plastic: a diffuse base under a dielectric coating (after Mitsuba 0.6 `roughplastic` /
// `plastic`). The coating reflects through a microfacet lobe (or a delta when alpha == 0);
// light refracted into the coating is scattered diffusely by the base, and the internal
// reflections off the coating are accounted for by the average internal reflectance.
// A smooth coating lets light through by the Fresnel transmittance 1 - F; a rough one, as
// in Mitsuba's `roughplastic`, by the rough transmittance of its microfacet boundary (in
// and out, and averaged over the inside for the internal reflectance), which at grazing
// angles is far larger. Reflectances and roughness may be textures. One-sided.
#include <optional>
#include <utility>

#include "emlt/core/warp.h"
#include "emlt/scene/materials.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/microfacet.h"
#include "src/scene/materials/rough_transmittance.h"
#include "src/scene/materials/texture_param.h"

namespace emlt {
namespace {

class RoughPlastic final : public Bsdf {
 public:
  RoughPlastic(TexturePtr alpha, MicrofacetType type, TexturePtr diffuse, TexturePtr specular,
               float eta, bool nonlinear)
      : alpha_(std::move(alpha)), type_(type), diffuse_(std::move(diffuse)),
        specular_(std::move(specular)), eta_(eta), nonlinear_(nonlinear) {
    // A smooth coating is a delta lobe; that must be decided once, for the whole surface.
    smooth_ = alpha_.is_constant() && alpha_.average_at(Vec2(0.0f)) <= 0.0f;
    if (smooth_) {
      internal_reflectance_ = fresnel_diffuse_reflectance(1.0f / eta_);
    } else {
      // A textured roughness is tabulated over [0, 1] (values beyond read as 1).
      const float alpha = alpha_.is_constant() ? alpha_.average_at(Vec2(0.0f)) : 0.0f;
      const float alpha_max = alpha_.is_constant() ? 0.0f : 1.0f;
      entering_.emplace(type_, eta_, alpha, alpha_max);
      leaving_.emplace(type_, 1.0f / eta_, alpha, alpha_max);
      internal_reflectance_ = 1.0f - leaving_->diffuse(alpha);
    }
  }

  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Rgb(0.0f);
    return eval_at(parameters(ctx), wo, wi);
  }

  // Mixture of the two lobes' densities; for a smooth coating only the diffuse part, since
  // the delta lobe has no density.
  float pdf(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    const Parameters p = parameters(ctx);
    return pdf_at(p, wo, wi, specular_probability(p, wo.z));
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2& u) const override {
    if (wo.z <= 0.0f) return std::nullopt;
    const Parameters p = parameters(ctx);
    const float p_specular = specular_probability(p, wo.z);
    BsdfSample s;
    if (smooth_ && u_lobe < p_specular) {
      s.wi = Vec3(-wo.x, -wo.y, wo.z);
      const float fresnel = fresnel_dielectric(wo.z, eta_);
      s.pdf = p_specular;
      s.pdf_reverse = p_specular;  // same cosine from wi, same choice
      s.value = p.ks * (fresnel / wo.z);
      s.weight = p.ks * (fresnel / p_specular);
      s.lobe = kLobeSpecular | kLobeReflection;
      if (!is_finite(s.value)) return std::nullopt;
      return s;
    }
    if (u_lobe < p_specular) {
      const Vec3 m = p.distribution.sample_normal(wo, u);
      if (glm::dot(wo, m) <= 0.0f) return std::nullopt;
      s.wi = reflect_about(wo, m);
      s.lobe = kLobeGlossy | kLobeReflection;
    } else {
      s.wi = square_to_cosine_hemisphere(u);
      s.lobe = kLobeDiffuse | kLobeReflection;
    }
    if (s.wi.z <= 0.0f) return std::nullopt;
    s.pdf = pdf_at(p, wo, s.wi, p_specular);
    if (s.pdf <= 0.0f || !std::isfinite(s.pdf)) return std::nullopt;
    s.value = eval_at(p, wo, s.wi);
    s.weight = s.value * (s.wi.z / s.pdf);
    if (!is_finite(s.weight)) return std::nullopt;
    s.pdf_reverse = pdf_at(p, s.wi, wo, specular_probability(p, s.wi.z));
    return s;
  }

  uint32_t lobes() const override {
    return kLobeDiffuse | kLobeReflection | (smooth_ ? kLobeSpecular : kLobeGlossy);
  }
  std::string name() const override { return smooth_ ? "plastic" : "rough_plastic"; }
  // Mitsuba's components: the coating's microfacet reflection and the diffuse base.
  RoughComponents rough_components(const BsdfContext& ctx) const override {
    RoughComponents r;
    const float inf = std::numeric_limits<float>::infinity();
    r.count = smooth_ ? 1 : 2;
    r.alpha[0] = inf;
    if (!smooth_) r.alpha[1] = parameters(ctx).alpha;
    return r;
  }

 private:
  // The textured parameters at one point, read once per call: a sample reads them for its
  // lobe choice, both densities and the value, and a bitmap lookup is the dearest part.
  struct Parameters {
    Rgb kd, ks;
    // The roughness clamped as the microfacet distribution clamps it (Mitsuba looks its
    // transmittance up at that value too); 0 for a smooth coating.
    float alpha;
    MicrofacetDistribution distribution;
  };

  Parameters parameters(const BsdfContext& ctx) const {
    const float alpha = alpha_.average_at(ctx);
    return Parameters{diffuse_.at(ctx), specular_.at(ctx),
                      smooth_ ? 0.0f : glm::max(alpha, MicrofacetDistribution::kMinAlpha),
                      MicrofacetDistribution(type_, alpha)};
  }

  Rgb eval_at(const Parameters& p, const Vec3& wo, const Vec3& wi) const {
    Rgb result = diffuse_value(p, wo, wi);
    if (!smooth_) {
      // Coating: f = Ks F(wo.h) D(h) G1(wo, h) G1(wi, h) / (4 cos_o cos_i) (Mitsuba's
      // separable Smith masking-shadowing)
      const Vec3 h = reflection_half_vector(wo, wi);
      const float fresnel = fresnel_dielectric(glm::dot(wo, h), eta_);
      result += p.ks * (fresnel * p.distribution.D(h) * p.distribution.G(wo, wi, h) /
                        (4.0f * wo.z * wi.z));
    }
    return result;
  }

  // The density of wi given wo, whose lobe choice is p_specular (specular_probability at
  // wo.z).
  float pdf_at(const Parameters& p, const Vec3& wo, const Vec3& wi, float p_specular) const {
    float density = (1.0f - p_specular) * cosine_hemisphere_pdf(wi);
    if (!smooth_) density += p_specular * p.distribution.reflection_pdf(wo, wi);
    return density;
  }

  // Fraction of the light from direction cos_theta that the coating lets through.
  float transmittance(float cos_theta, float alpha) const {
    return smooth_ ? 1.0f - fresnel_dielectric(cos_theta, eta_) : (*entering_)(cos_theta, alpha);
  }

  // Base seen through the coating: Kd' / pi * T(cos_i) T(cos_o) / eta^2, with
  // Kd' = Kd / (1 - Fdr) (linear: with a white base the lobe then reflects exactly the
  // T(cos_o) that the coating lets in) or Kd / (1 - Kd Fdr) (nonlinear). Fdr is the
  // coating's reflectance averaged over the inside: smooth, 1 minus the cosine-weighted
  // mean of 1 - F; rough, of the rough transmittance (with a textured roughness, at the
  // point's alpha; with a constant one, precomputed).
  Rgb diffuse_value(const Parameters& p, const Vec3& wo, const Vec3& wi) const {
    const Rgb& kd = p.kd;
    const float fdr = smooth_ || alpha_.is_constant() ? internal_reflectance_
                                                      : 1.0f - leaving_->diffuse(p.alpha);
    const Rgb base = nonlinear_ ? kd / glm::max(Rgb(1.0f) - kd * fdr, Rgb(1e-6f))
                                : kd / glm::max(1.0f - fdr, 1e-6f);
    const float transmit_in = transmittance(wi.z, p.alpha);
    const float transmit_out = transmittance(wo.z, p.alpha);
    return base * (kInvPi * transmit_in * transmit_out / (eta_ * eta_));
  }

  // Probability of sampling the coating lobe: its albedo estimate (the light the coating
  // does not let through) against the base's, so that bright coatings at grazing angles
  // get most samples.
  float specular_probability(const Parameters& p, float cos_o) const {
    const float specular_albedo = (p.ks.x + p.ks.y + p.ks.z) / 3.0f;
    const float diffuse_albedo = (p.kd.x + p.kd.y + p.kd.z) / 3.0f;
    const float total = specular_albedo + diffuse_albedo;
    const float specular_weight = total > 0.0f ? specular_albedo / total : 0.5f;
    const float reflected = 1.0f - transmittance(cos_o, p.alpha);
    const float specular = reflected * specular_weight;
    const float diffuse = (1.0f - reflected) * (1.0f - specular_weight);
    return specular + diffuse > 0.0f ? specular / (specular + diffuse) : specular_weight;
  }

  TextureParam alpha_;
  MicrofacetType type_;
  TextureParam diffuse_, specular_;
  float eta_;  // n_inside / n_outside of the coating
  bool nonlinear_;
  bool smooth_ = false;
  float internal_reflectance_ = 0.0f;
  // Rough coatings only: transmittance into the coating, and out of it (for Fdr).
  std::optional<RoughTransmittance> entering_, leaving_;
};

}  // namespace

BsdfPtr make_rough_plastic(float alpha, const Rgb& diffuse_reflectance,
                           const Rgb& specular_reflectance, float int_ior, float ext_ior) {
  return make_rough_plastic(make_constant_texture(Rgb(glm::max(alpha, 0.0f))),
                            make_constant_texture(glm::max(diffuse_reflectance, Rgb(0.0f))),
                            make_constant_texture(glm::max(specular_reflectance, Rgb(0.0f))),
                            int_ior, ext_ior);
}

BsdfPtr make_rough_plastic(TexturePtr alpha, TexturePtr diffuse_reflectance,
                           TexturePtr specular_reflectance, float int_ior, float ext_ior,
                           bool nonlinear, MicrofacetType distribution) {
  return std::make_shared<RoughPlastic>(std::move(alpha), distribution,
                                        std::move(diffuse_reflectance),
                                        std::move(specular_reflectance), int_ior / ext_ior,
                                        nonlinear);
}

}  // namespace emlt
