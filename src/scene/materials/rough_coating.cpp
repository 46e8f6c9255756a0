// Mitsuba 0.6's `roughcoating`: a rough dielectric interface over any nested BSDF, in
// Mitsuba's model (see coating_layer.h). The interface reflects through a microfacet lobe,
//   Ks F(wo.h) D(h) G1(wo, h) G1(wi, h) / (4 |cos_o| |cos_i|),
// on either side; the nested BSDF is seen at the directions refracted by the smooth
// interface's law (the mean microfacet), weighted by the rough transmittance T(|cos|) of
// the microfacet boundary in and out (rough_transmittance.h, Mitsuba's tables), by the
// layer's absorption and by 1 / eta^2. Sampling picks the microfacet lobe with Mitsuba's
// probability (1 - T(cos_o), reweighted for absorption), and returns the value and
// density of the whole mixture. The roughness may be a texture.
//
// One of Mitsuba's choices is kept for its images' sake: a delta lobe of the nested BSDF is
// weighted as if it were the only way out, by its own probability but not by that of the
// nested BSDF's choice (Mitsuba's pdf leaves the mixture weight out for discrete
// measures). Its samples carry f / p_nested_lobe while they are drawn with probability
// (1 - p_specular) p_nested_lobe, so Mitsuba renders the delta darkened by
// 1 - p_specular(cos_o); that is what this BSDF's delta is (and so it is not reciprocal).
#include <algorithm>
#include <optional>
#include <utility>

#include "emlt/scene/materials.h"
#include "src/scene/materials/coating_layer.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/microfacet.h"
#include "src/scene/materials/rough_transmittance.h"

namespace emlt {
namespace {

// Mitsuba's rough transmittance tables go up to alpha 4.
constexpr float kMaxTabulatedAlpha = 4.0f;

class RoughCoating final : public Bsdf {
 public:
  RoughCoating(BsdfPtr nested, CoatingLayer layer, const Rgb& specular, TexturePtr alpha,
               MicrofacetType type)
      : nested_(std::move(nested)),
        layer_(std::move(layer)),
        specular_(specular),
        alpha_(std::move(alpha)),
        type_(type) {
    // A constant roughness needs one row of the table; a texture one over its range.
    float alpha_max = 0.0f;
    if (!alpha_.is_constant()) {
      constexpr int kSide = 128;
      for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i)
          alpha_max =
              std::max(alpha_max, alpha_.average_at(Vec2((i + 0.5f) / kSide, (j + 0.5f) / kSide)));
      alpha_max = std::clamp(alpha_max, 1.0f, kMaxTabulatedAlpha);
    }
    transmittance_.emplace(type_, layer_.eta(), clamped_alpha(BsdfContext{}), alpha_max);
  }

  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    return eval_at(ctx, parameters(ctx), wo, wi);
  }

  float pdf(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    return pdf_at(ctx, parameters(ctx), wo, wi);
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2& u) const override {
    if (wo.z == 0.0f) return std::nullopt;
    const Parameters p = parameters(ctx);
    const float p_specular = specular_probability(p, wo);
    BsdfSample s;
    if (u_lobe < p_specular) {
      // The microfacet lobe, sampled above the surface and mirrored back to wo's side.
      const float side = wo.z < 0.0f ? -1.0f : 1.0f;
      const Vec3 up(wo.x, wo.y, std::abs(wo.z));
      const Vec3 m = p.distribution.sample_normal(up, u);
      if (glm::dot(up, m) <= 0.0f) return std::nullopt;
      const Vec3 reflected = reflect_about(up, m);
      if (reflected.z <= 0.0f) return std::nullopt;
      s.wi = Vec3(reflected.x, reflected.y, side * reflected.z);
      s.lobe = kLobeGlossy | kLobeReflection;
    } else {
      const float p_nested = 1.0f - p_specular;
      const float u_nested = std::min((u_lobe - p_specular) / p_nested, kOneMinusEpsilon);
      const Vec3 wo_in = layer_.refract_in(wo);
      if (wo_in.z == 0.0f) return std::nullopt;
      const std::optional<BsdfSample> inner = nested_->sample(ctx, wo_in, u_nested, u);
      if (!inner) return std::nullopt;
      s.wi = layer_.refract_out(inner->wi);
      if (s.wi.z == 0.0f || inner->wi.z == 0.0f) return std::nullopt;
      s.lobe = inner->lobe;
      s.eta = inner->eta;
      if (inner->is_delta()) {
        // Mitsuba's weight for a nested delta (see the top of the file): the nested one,
        // through the interface and the layer, not divided by the choice of the nested BSDF.
        s.weight = inner->weight * through(ctx, p, wo, s.wi, wo_in, inner->wi);
        s.pdf = inner->pdf * p_nested;
        s.pdf_reverse = inner->pdf_reverse * (1.0f - specular_probability(p, s.wi));
        s.value = s.weight * (s.pdf / std::abs(s.wi.z));
        if (!(s.pdf > 0.0f) || !is_finite(s.weight) || !is_finite(s.value)) return std::nullopt;
        return s;
      }
    }
    s.pdf = pdf_at(ctx, p, wo, s.wi);
    if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
    s.value = eval_at(ctx, p, wo, s.wi);
    s.weight = s.value * (std::abs(s.wi.z) / s.pdf);
    if (!is_finite(s.weight)) return std::nullopt;
    s.pdf_reverse = pdf_at(ctx, p, s.wi, wo);
    return s;
  }

  uint32_t lobes() const override { return nested_->lobes() | kLobeGlossy | kLobeReflection; }
  std::string name() const override { return "roughcoating"; }
  bool is_anisotropic() const override { return nested_->is_anisotropic(); }

 private:
  // The roughness at a point, read once per call (a bitmap lookup is the dearest part).
  struct Parameters {
    float alpha;  // clamped as the distribution clamps it (Mitsuba looks T up at that)
    MicrofacetDistribution distribution;
  };

  float clamped_alpha(const BsdfContext& ctx) const {
    return std::max(alpha_.average_at(ctx), MicrofacetDistribution::kMinAlpha);
  }
  Parameters parameters(const BsdfContext& ctx) const {
    const float alpha = clamped_alpha(ctx);
    return Parameters{alpha, MicrofacetDistribution(type_, alpha)};
  }

  // The rough transmittance of the interface for light from w (either side).
  float transmittance(const Parameters& p, const Vec3& w) const {
    return (*transmittance_)(std::abs(w.z), p.alpha);
  }

  float specular_probability(const Parameters& p, const Vec3& wo) const {
    return layer_.specular_probability(1.0f - transmittance(p, wo));
  }

  // What reaches the nested BSDF and comes back out, for the outside pair (wo, wi) and
  // the refracted one: T(cos_o) T(cos_i) A(wo', wi').
  Rgb through(const BsdfContext& ctx, const Parameters& p, const Vec3& wo, const Vec3& wi,
              const Vec3& wo_in, const Vec3& wi_in) const {
    return layer_.attenuation(ctx, wo_in, wi_in) * (transmittance(p, wo) * transmittance(p, wi));
  }

  Rgb eval_at(const BsdfContext& ctx, const Parameters& p, const Vec3& wo, const Vec3& wi) const {
    Rgb result(0.0f);
    if (wo.z * wi.z > 0.0f) {
      // The distribution is symmetric under z -> -z: the lobe below mirrors the one above.
      const Vec3 o(wo.x, wo.y, std::abs(wo.z)), i(wi.x, wi.y, std::abs(wi.z));
      const Vec3 h = reflection_half_vector(o, i);
      const float fresnel = fresnel_dielectric(std::abs(glm::dot(o, h)), layer_.eta());
      result += specular_ *
                (fresnel * p.distribution.D(h) * p.distribution.G(o, i, h) / (4.0f * o.z * i.z));
    }
    const Vec3 wo_in = layer_.refract_in(wo), wi_in = layer_.refract_in(wi);
    if (wo_in.z != 0.0f && wi_in.z != 0.0f) {
      const float eta = layer_.eta();
      result +=
          nested_->eval(ctx, wo_in, wi_in) * through(ctx, p, wo, wi, wo_in, wi_in) / (eta * eta);
    }
    return result;
  }

  float pdf_at(const BsdfContext& ctx, const Parameters& p, const Vec3& wo, const Vec3& wi) const {
    if (wo.z == 0.0f) return 0.0f;
    const float p_specular = specular_probability(p, wo);
    float density = 0.0f;
    if (wo.z * wi.z > 0.0f) {
      const Vec3 o(wo.x, wo.y, std::abs(wo.z)), i(wi.x, wi.y, std::abs(wi.z));
      density += p_specular * p.distribution.reflection_pdf(o, i);
    }
    const Vec3 wo_in = layer_.refract_in(wo), wi_in = layer_.refract_in(wi);
    if (wo_in.z != 0.0f && wi_in.z != 0.0f)
      density += (1.0f - p_specular) * nested_->pdf(ctx, wo_in, wi_in) * layer_.jacobian(wi, wi_in);
    return density;
  }

  BsdfPtr nested_;
  CoatingLayer layer_;
  Rgb specular_;
  TextureParam alpha_;
  MicrofacetType type_;
  std::optional<RoughTransmittance> transmittance_;  // into the layer, from outside
};

}  // namespace

BsdfPtr make_rough_coating(BsdfPtr nested, TexturePtr alpha, MicrofacetType distribution,
                           float int_ior, float ext_ior, float thickness, TexturePtr sigma_a,
                           const Rgb& specular_reflectance) {
  if (!sigma_a) sigma_a = make_constant_texture(Rgb(0.0f));
  return std::make_shared<RoughCoating>(
      std::move(nested), CoatingLayer(int_ior / ext_ior, thickness, std::move(sigma_a)),
      glm::max(specular_reflectance, Rgb(0.0f)), std::move(alpha), distribution);
}

}  // namespace emlt
