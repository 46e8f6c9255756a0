// Rough diffuse reflector: Oren and Nayar's V-groove model (1994) as Mitsuba 0.6's
// `roughdiffuse` evaluates it, one-sided. The full model keeps the paper's single-scattering
// terms C1..C3 and its interreflection term C4 (which goes with the square of the albedo);
// the fast approximation keeps only A + B max(0, cos dphi) sin(alpha) tan(beta). The
// roughness `alpha` is an RMS slope like the microfacet BSDFs' alpha; Mitsuba converts it
// to the paper's standard deviation of facet angles as sigma = alpha / sqrt(2). Both may be
// textures (alpha: the channel mean). Sampled by the cosine-weighted hemisphere, which is
// close to the lobe at every roughness.
#include <utility>

#include "emlt/core/warp.h"
#include "emlt/scene/materials.h"
#include "src/scene/materials/texture_param.h"

namespace emlt {
namespace {

// Below this sine a direction counts as the normal and has no azimuth (Mitsuba's single
// precision Epsilon): the azimuthal terms are dropped rather than read from noise.
constexpr float kNoAzimuth = 1e-4f;

// See RoughDiffuse::value.
constexpr float kGrazing = 1e-7f;

float sin_theta(const Vec3& w) {
  return safe_sqrt(1.0f - w.z * w.z);
}

// cos(phi_a - phi_b) from each direction's own cos phi and sin phi, each clamped to [-1, 1]
// as a direction's azimuth is read alone; 0 when either lies along the normal.
float cos_azimuth_difference(const Vec3& a, float sin_a, const Vec3& b, float sin_b) {
  if (sin_a <= kNoAzimuth || sin_b <= kNoAzimuth) return 0.0f;
  const float cos_a = glm::clamp(a.x / sin_a, -1.0f, 1.0f);
  const float sin_phi_a = glm::clamp(a.y / sin_a, -1.0f, 1.0f);
  const float cos_b = glm::clamp(b.x / sin_b, -1.0f, 1.0f);
  const float sin_phi_b = glm::clamp(b.y / sin_b, -1.0f, 1.0f);
  return cos_a * cos_b + sin_phi_a * sin_phi_b;
}

class RoughDiffuse final : public Bsdf {
 public:
  RoughDiffuse(TexturePtr reflectance, TexturePtr alpha, bool fast_approximation)
      : reflectance_(std::move(reflectance)),
        alpha_(std::move(alpha)),
        fast_approximation_(fast_approximation) {}

  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Rgb(0.0f);
    return value(reflectance_.at(ctx), alpha_.average_at(ctx), wo, wi);
  }

  float pdf(const BsdfContext&, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    return cosine_hemisphere_pdf(wi);
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float,
                                   const Vec2& u) const override {
    if (wo.z <= 0.0f) return std::nullopt;
    BsdfSample s;
    s.wi = square_to_cosine_hemisphere(u);
    s.pdf = cosine_hemisphere_pdf(s.wi);
    if (s.pdf <= 0.0f) return std::nullopt;
    s.value = value(reflectance_.at(ctx), alpha_.average_at(ctx), wo, s.wi);
    s.weight = s.value * (s.wi.z / s.pdf);
    if (!is_finite(s.weight)) return std::nullopt;
    s.pdf_reverse = cosine_hemisphere_pdf(wo);
    s.lobe = kLobeGlossy | kLobeReflection;  // Mitsuba classes it as glossy, not diffuse
    return s;
  }

  uint32_t lobes() const override { return kLobeGlossy | kLobeReflection; }
  std::string name() const override {
    return fast_approximation_ ? "rough_diffuse_fast" : "rough_diffuse";
  }

 private:
  // f(wo, wi) for both directions above the surface. Symmetric in wo and wi: alpha is the
  // larger of the two polar angles, beta the smaller.
  Rgb value(const Rgb& rho, float alpha, const Vec3& wo, const Vec3& wi) const {
    const float sigma2 = 0.5f * alpha * alpha;  // (alpha / sqrt 2)^2
    const float sin_o = sin_theta(wo), sin_i = sin_theta(wi);
    const float cos_dphi = cos_azimuth_difference(wo, sin_o, wi, sin_i);
    // The direction nearer the normal gives beta, the other alpha.
    const bool wi_nearer = wi.z > wo.z;
    const float sin_alpha = wi_nearer ? sin_o : sin_i;
    const float sin_beta = wi_nearer ? sin_i : sin_o;
    // Both tangents below are unbounded only when both directions graze the surface (within
    // 1e-7 of it), where every contribution carries their vanishing cosines: bounded there so
    // that a value never becomes infinite, which a Metropolis chain cannot weigh.
    const float tan_beta = (wi_nearer ? sin_i : sin_o) / glm::max(glm::max(wi.z, wo.z), kGrazing);
    const float c1 = 1.0f - 0.5f * sigma2 / (sigma2 + 0.33f);
    const float grooves = sigma2 / (sigma2 + 0.09f);
    if (fast_approximation_) {
      const float b = 0.45f * grooves;
      return rho * (kInvPi * (c1 + b * glm::max(cos_dphi, 0.0f) * sin_alpha * tan_beta));
    }
    const float theta_alpha = safe_acos(wi_nearer ? wo.z : wi.z);
    const float theta_beta = safe_acos(wi_nearer ? wi.z : wo.z);
    const float beta_fraction = 2.0f * kInvPi * theta_beta;  // 2 beta / pi
    const float angle_product = 4.0f * kInvPi * kInvPi * theta_alpha * theta_beta;
    float c2 = 0.45f * grooves;
    c2 *= cos_dphi > 0.0f ? sin_alpha : sin_alpha - beta_fraction * beta_fraction * beta_fraction;
    const float c3 = 0.125f * grooves * angle_product * angle_product;
    const float c4 = 0.17f * sigma2 / (sigma2 + 0.13f);
    // tan((alpha + beta) / 2) by the half-angle identity.
    const float tan_half_sum = (sin_alpha + sin_beta) / glm::max(wo.z + wi.z, kGrazing);
    const float single =
        c1 + cos_dphi * c2 * tan_beta + (1.0f - std::abs(cos_dphi)) * c3 * tan_half_sum;
    const float interreflected = c4 * (1.0f - cos_dphi * beta_fraction * beta_fraction);
    // For rough, dark surfaces the full model turns negative where both directions graze the
    // surface from opposite sides (alpha 1.2, albedo 0.2: down to -0.003 past 80 degrees);
    // Mitsuba would subtract that light, a path's weight here is never negative.
    return glm::max((rho * single + rho * rho * interreflected) * kInvPi, Rgb(0.0f));
  }

  TextureParam reflectance_;
  TextureParam alpha_;
  bool fast_approximation_;
};

}  // namespace

BsdfPtr make_rough_diffuse(TexturePtr reflectance, TexturePtr alpha, bool fast_approximation) {
  return std::make_shared<RoughDiffuse>(std::move(reflectance), std::move(alpha),
                                        fast_approximation);
}

BsdfPtr make_rough_diffuse(const Rgb& reflectance, float alpha, bool fast_approximation) {
  return make_rough_diffuse(make_constant_texture(glm::max(reflectance, Rgb(0.0f))),
                            make_constant_texture(Rgb(glm::max(alpha, 0.0f))), fast_approximation);
}

}  // namespace emlt
