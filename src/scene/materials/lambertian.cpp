// Ideal diffuse reflector, one-sided.
#include "emlt/core/warp.h"
#include "emlt/scene/materials.h"

namespace emlt {
namespace {

class Lambertian final : public Bsdf {
 public:
  explicit Lambertian(const Rgb& reflectance) : reflectance_(reflectance) {}

  Rgb eval(const BsdfContext&, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Rgb(0.0f);
    return reflectance_ * kInvPi;
  }

  float pdf(const BsdfContext&, const Vec3& wo, const Vec3& wi) const override {
    if (wo.z <= 0.0f) return 0.0f;
    return cosine_hemisphere_pdf(wi);
  }

  std::optional<BsdfSample> sample(const BsdfContext&, const Vec3& wo, float,
                                   const Vec2& u) const override {
    if (wo.z <= 0.0f) return std::nullopt;
    BsdfSample s;
    s.wi = square_to_cosine_hemisphere(u);
    s.pdf = cosine_hemisphere_pdf(s.wi);
    if (s.pdf <= 0.0f) return std::nullopt;
    s.value = reflectance_ * kInvPi;
    s.weight = reflectance_;  // (R / pi) * cos / (cos / pi)
    s.pdf_reverse = cosine_hemisphere_pdf(wo);
    s.lobe = kLobeDiffuse | kLobeReflection;
    return s;
  }

  uint32_t lobes() const override { return kLobeDiffuse | kLobeReflection; }
  std::string name() const override { return "lambertian"; }

 private:
  Rgb reflectance_;
};

}  // namespace

BsdfPtr make_lambertian(const Rgb& reflectance) {
  return std::make_shared<Lambertian>(glm::max(reflectance, Rgb(0.0f)));
}

}  // namespace emlt
