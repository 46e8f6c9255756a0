// Ideal diffuse reflector, one-sided; the reflectance may be a texture.
#include <utility>

#include "emlt/core/warp.h"
#include "emlt/scene/materials.h"
#include "src/scene/materials/texture_param.h"

namespace emlt {
namespace {

class Lambertian final : public Bsdf {
 public:
  explicit Lambertian(TexturePtr reflectance) : reflectance_(std::move(reflectance)) {}

  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Rgb(0.0f);
    return reflectance_.at(ctx) * kInvPi;
  }

  float pdf(const BsdfContext&, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f) return 0.0f;
    return cosine_hemisphere_pdf(wi);
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float,
                                   const Vec2& u) const override {
    if (wo.z <= 0.0f) return std::nullopt;
    BsdfSample s;
    s.wi = square_to_cosine_hemisphere(u);
    s.pdf = cosine_hemisphere_pdf(s.wi);
    if (s.pdf <= 0.0f) return std::nullopt;
    const Rgb reflectance = reflectance_.at(ctx);
    s.value = reflectance * kInvPi;
    s.weight = reflectance;  // (R / pi) * cos / (cos / pi)
    s.pdf_reverse = cosine_hemisphere_pdf(wo);
    s.lobe = kLobeDiffuse | kLobeReflection;
    return s;
  }

  uint32_t lobes() const override { return kLobeDiffuse | kLobeReflection; }
  std::string name() const override { return "lambertian"; }
  std::optional<PhongLobes> phong_lobes(const BsdfContext& ctx) const override {
    return PhongLobes{reflectance_.at(ctx), Rgb(0.0f), 0.0f};
  }

 private:
  TextureParam reflectance_;
};

}  // namespace

BsdfPtr make_lambertian(const Rgb& reflectance) {
  return make_lambertian(make_constant_texture(glm::max(reflectance, Rgb(0.0f))));
}

BsdfPtr make_lambertian(TexturePtr reflectance) {
  return std::make_shared<Lambertian>(std::move(reflectance));
}

}  // namespace emlt
