// Mitsuba 0.6's `coating`: a smooth dielectric interface over any nested BSDF, in
// Mitsuba's model (see coating_layer.h): the interface reflects specularly, a delta
// weighted by the Fresnel reflectance F(cos_o) and specularReflectance, on either side;
// what it lets through sees the nested BSDF at the refracted directions,
//   f(wo, wi) = f_nested(wo', wi') (1 - F(cos_o)) (1 - F(cos_i)) A(wo', wi') / eta^2,
// A the layer's absorption. Sampling picks the reflection with Mitsuba's probability
// (coating_layer.h), otherwise samples the nested BSDF inside the layer and refracts its
// direction out; a delta lobe of the nested BSDF stays a delta (a mirror under a coating
// is a mirror weighted by the layer). Refraction keeps the azimuth, so an anisotropic
// nested BSDF keeps its frame.
#include <optional>
#include <utility>

#include "emlt/scene/materials.h"
#include "src/scene/materials/coating_layer.h"
#include "src/scene/materials/fresnel.h"

namespace emlt {
namespace {

class SmoothCoating final : public Bsdf {
 public:
  SmoothCoating(BsdfPtr nested, CoatingLayer layer, const Rgb& specular)
      : nested_(std::move(nested)), layer_(std::move(layer)), specular_(specular) {}

  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    const float fresnel_o = reflectance(wo), fresnel_i = reflectance(wi);
    if (fresnel_o >= 1.0f || fresnel_i >= 1.0f) return Rgb(0.0f);  // nothing gets in
    const Vec3 wo_in = layer_.refract_in(wo), wi_in = layer_.refract_in(wi);
    if (wo_in.z == 0.0f || wi_in.z == 0.0f) return Rgb(0.0f);
    const float eta = layer_.eta();
    return nested_->eval(ctx, wo_in, wi_in) * layer_.attenuation(ctx, wo_in, wi_in) *
           ((1.0f - fresnel_o) * (1.0f - fresnel_i) / (eta * eta));
  }

  float pdf(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    const float fresnel_o = reflectance(wo), fresnel_i = reflectance(wi);
    if (fresnel_o >= 1.0f || fresnel_i >= 1.0f) return 0.0f;
    const Vec3 wo_in = layer_.refract_in(wo), wi_in = layer_.refract_in(wi);
    if (wo_in.z == 0.0f || wi_in.z == 0.0f) return 0.0f;
    return nested_->pdf(ctx, wo_in, wi_in) * layer_.jacobian(wi, wi_in) *
           (1.0f - layer_.specular_probability(fresnel_o));
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2& u) const override {
    if (wo.z == 0.0f) return std::nullopt;
    const float fresnel_o = reflectance(wo);
    const float p_specular = layer_.specular_probability(fresnel_o);
    BsdfSample s;
    if (u_lobe < p_specular) {
      s.wi = Vec3(-wo.x, -wo.y, wo.z);
      s.pdf = s.pdf_reverse = p_specular;  // the same cosine from wi, the same choice
      s.weight = specular_ * (fresnel_o / p_specular);
      s.value = specular_ * (fresnel_o / std::abs(wo.z));
      s.lobe = kLobeSpecular | kLobeReflection;
      return s;
    }
    if (fresnel_o >= 1.0f) return std::nullopt;
    const float p_nested = 1.0f - p_specular;
    // The rest of u_lobe, rescaled, chooses among the nested BSDF's lobes.
    const float u_nested = glm::min((u_lobe - p_specular) / p_nested, kOneMinusEpsilon);
    const Vec3 wo_in = layer_.refract_in(wo);
    if (wo_in.z == 0.0f) return std::nullopt;
    const std::optional<BsdfSample> inner = nested_->sample(ctx, wo_in, u_nested, u);
    if (!inner) return std::nullopt;
    const Vec3 wi_in = inner->wi;
    s.wi = layer_.refract_out(wi_in);
    if (s.wi.z == 0.0f || wi_in.z == 0.0f) return std::nullopt;
    const float fresnel_i = reflectance(s.wi);
    if (fresnel_i >= 1.0f) return std::nullopt;
    const Rgb through =
        layer_.attenuation(ctx, wo_in, wi_in) * ((1.0f - fresnel_o) * (1.0f - fresnel_i));
    s.weight = inner->weight * through / p_nested;
    s.lobe = inner->lobe;
    s.eta = inner->eta;
    const float p_reverse = 1.0f - layer_.specular_probability(fresnel_i);
    if (inner->is_delta()) {
      // A delta keeps its discrete probability: no change of measure.
      s.pdf = inner->pdf * p_nested;
      s.pdf_reverse = inner->pdf_reverse * p_reverse;
    } else {
      s.pdf = inner->pdf * p_nested * layer_.jacobian(s.wi, wi_in);
      s.pdf_reverse = inner->pdf_reverse * p_reverse * layer_.jacobian(wo, wo_in);
    }
    s.value = s.weight * (s.pdf / std::abs(s.wi.z));
    if (!(s.pdf > 0.0f) || !is_finite(s.weight) || !is_finite(s.value)) return std::nullopt;
    return s;
  }

  uint32_t lobes() const override { return nested_->lobes() | kLobeSpecular | kLobeReflection; }
  std::string name() const override { return "coating"; }
  bool is_anisotropic() const override { return nested_->is_anisotropic(); }

 private:
  // The interface's Fresnel reflectance for w, always seen from the outside (Mitsuba's
  // layer is the same from either side).
  float reflectance(const Vec3& w) const { return fresnel_dielectric(std::abs(w.z), layer_.eta()); }

  BsdfPtr nested_;
  CoatingLayer layer_;
  Rgb specular_;
};

}  // namespace

BsdfPtr make_coating(BsdfPtr nested, float int_ior, float ext_ior, float thickness,
                     TexturePtr sigma_a, const Rgb& specular_reflectance) {
  if (!sigma_a) sigma_a = make_constant_texture(Rgb(0.0f));
  return std::make_shared<SmoothCoating>(
      std::move(nested), CoatingLayer(int_ior / ext_ior, thickness, std::move(sigma_a)),
      glm::max(specular_reflectance, Rgb(0.0f)));
}

}  // namespace emlt
