// Ideal specular reflector (a perfect conductor), one-sided.
#include "emlt/scene/materials.h"

namespace emlt {
namespace {

class Mirror final : public Bsdf {
 public:
  explicit Mirror(const Rgb& reflectance) : reflectance_(reflectance) {}

  // A Dirac delta has no finite value or density at any particular pair of directions.
  Rgb eval(const BsdfContext&, const Vec3&, const Vec3&) const override { return Rgb(0.0f); }
  float pdf(const BsdfContext&, const Vec3&, const Vec3&) const override { return 0.0f; }

  std::optional<BsdfSample> sample(const BsdfContext&, const Vec3& wo, float,
                                   const Vec2&) const override {
    if (wo.z <= 0.0f) return std::nullopt;
    BsdfSample s;
    s.wi = Vec3(-wo.x, -wo.y, wo.z);
    s.pdf = 1.0f;
    s.pdf_reverse = 1.0f;
    s.value = reflectance_ / s.wi.z;
    s.weight = reflectance_;
    s.lobe = kLobeSpecular | kLobeReflection;
    return s;
  }

  uint32_t lobes() const override { return kLobeSpecular | kLobeReflection; }
  std::string name() const override { return "mirror"; }

 private:
  Rgb reflectance_;
};

}  // namespace

BsdfPtr make_mirror(const Rgb& reflectance) {
  return std::make_shared<Mirror>(glm::max(reflectance, Rgb(0.0f)));
}

}  // namespace emlt
