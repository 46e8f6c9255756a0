// Modified Phong reflector (Lafortune and Willems 1994) as Mitsuba 0.6's `phong`: a
// Lambertian term kd / pi plus a normalised lobe about the mirror direction,
// ks (n + 2) / (2 pi) cos^n(angle to the mirror direction), which never reflects more than
// ks. One-sided. Sampling picks the lobe by the reflectances' average luminances (fixed for
// the whole surface, as Mitsuba does), then the cosine hemisphere or cos^n about the mirror
// direction; the density is that mixture whichever lobe was drawn.
#include <utility>

#include "emlt/core/warp.h"
#include "emlt/scene/materials.h"
#include "src/scene/materials/texture_average.h"
#include "src/scene/materials/texture_param.h"

namespace emlt {
namespace {

Vec3 mirror_direction(const Vec3& w) {
  return Vec3(-w.x, -w.y, w.z);
}

class Phong final : public Bsdf {
 public:
  Phong(TexturePtr exponent, TexturePtr specular, TexturePtr diffuse)
      : exponent_(std::move(exponent)),
        specular_(std::move(specular)),
        diffuse_(std::move(diffuse)) {
    specular_probability_ = specular_lobe_probability(specular_.texture(), diffuse_.texture());
  }

  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Rgb(0.0f);
    const Parameters p = parameters(ctx);
    return value(p, wo, wi);
  }

  float pdf(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    return density(exponent_.average_at(ctx), wo, wi);
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2& u) const override {
    if (wo.z <= 0.0f) return std::nullopt;
    const Parameters p = parameters(ctx);
    BsdfSample s;
    if (u_lobe < specular_probability_) {
      // cos^n about the mirror direction: cos = u^(1 / (n + 1)).
      const float cos_lobe = std::pow(u.y, 1.0f / (p.exponent + 1.0f));
      const float sin_lobe = safe_sqrt(1.0f - cos_lobe * cos_lobe);
      const float phi = kTwoPi * u.x;
      const Vec3 local(sin_lobe * std::cos(phi), sin_lobe * std::sin(phi), cos_lobe);
      s.wi = glm::normalize(Frame(mirror_direction(wo)).to_world(local));
      s.lobe = kLobeGlossy | kLobeReflection;
    } else {
      s.wi = square_to_cosine_hemisphere(u);
      s.lobe = kLobeDiffuse | kLobeReflection;
    }
    if (s.wi.z <= 0.0f) return std::nullopt;
    s.pdf = density(p.exponent, wo, s.wi);
    if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
    s.value = value(p, wo, s.wi);
    s.weight = s.value * (s.wi.z / s.pdf);
    if (!is_finite(s.weight)) return std::nullopt;
    s.pdf_reverse = density(p.exponent, s.wi, wo);
    return s;
  }

  uint32_t lobes() const override { return kLobeDiffuse | kLobeGlossy | kLobeReflection; }
  std::string name() const override { return "phong"; }
  std::optional<PhongLobes> phong_lobes(const BsdfContext& ctx) const override {
    const Parameters p = parameters(ctx);
    return PhongLobes{p.kd, p.ks, p.exponent};
  }

 private:
  struct Parameters {
    float exponent;
    Rgb ks, kd;
  };
  Parameters parameters(const BsdfContext& ctx) const {
    return {exponent_.average_at(ctx), specular_.at(ctx), diffuse_.at(ctx)};
  }

  // The cosine between wi and wo's mirror direction (equal to wo's with wi's mirror).
  static float lobe_cosine(const Vec3& wo, const Vec3& wi) {
    return glm::dot(wi, mirror_direction(wo));
  }

  static Rgb value(const Parameters& p, const Vec3& wo, const Vec3& wi) {
    Rgb result = p.kd * kInvPi;
    const float c = lobe_cosine(wo, wi);
    if (c > 0.0f)
      result += p.ks * ((p.exponent + 2.0f) * (0.5f * kInvPi) * std::pow(c, p.exponent));
    return result;
  }

  float density(float exponent, const Vec3& wo, const Vec3& wi) const {
    const float c = lobe_cosine(wo, wi);
    const float lobe =
        c > 0.0f ? (exponent + 1.0f) * (0.5f * kInvPi) * std::pow(c, exponent) : 0.0f;
    return specular_probability_ * lobe + (1.0f - specular_probability_) * wi.z * kInvPi;
  }

  TextureParam exponent_, specular_, diffuse_;
  float specular_probability_ = 0.5f;
};

}  // namespace

BsdfPtr make_phong(TexturePtr exponent, TexturePtr specular_reflectance,
                   TexturePtr diffuse_reflectance) {
  return std::make_shared<Phong>(std::move(exponent), std::move(specular_reflectance),
                                 std::move(diffuse_reflectance));
}

BsdfPtr make_phong(float exponent, const Rgb& specular_reflectance,
                   const Rgb& diffuse_reflectance) {
  return make_phong(make_constant_texture(Rgb(glm::max(exponent, 0.0f))),
                    make_constant_texture(glm::max(specular_reflectance, Rgb(0.0f))),
                    make_constant_texture(glm::max(diffuse_reflectance, Rgb(0.0f))));
}

}  // namespace emlt
