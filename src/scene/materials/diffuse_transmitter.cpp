// Ideal diffuse transmitter as Mitsuba 0.6's `difftrans`: light arriving on either side
// leaves the other side with the cosine-weighted distribution, f = T / pi for wo and wi on
// opposite sides and 0 on the same side (no reflection). Both sides alike, no change of
// medium (eta 1), so radiance and importance transport agree. The transmittance may be a
// texture. Sampled by the cosine hemisphere on the side opposite wo.
#include <utility>

#include "emlt/core/warp.h"
#include "emlt/scene/materials.h"
#include "src/scene/materials/texture_param.h"

namespace emlt {
namespace {

class DiffuseTransmitter final : public Bsdf {
 public:
  explicit DiffuseTransmitter(TexturePtr transmittance)
      : transmittance_(std::move(transmittance)) {}

  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    if (!(wo.z * wi.z < 0.0f)) return Rgb(0.0f);
    return transmittance_.at(ctx) * kInvPi;
  }

  float pdf(const BsdfContext&, const Vec3& wo, const Vec3& wi) const override {
    if (!(wo.z * wi.z < 0.0f)) return 0.0f;
    return std::abs(wi.z) * kInvPi;
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float,
                                   const Vec2& u) const override {
    if (wo.z == 0.0f) return std::nullopt;  // in the surface: no side to leave from
    BsdfSample s;
    s.wi = square_to_cosine_hemisphere(u);
    if (wo.z > 0.0f) s.wi.z = -s.wi.z;
    s.pdf = std::abs(s.wi.z) * kInvPi;
    if (!(s.pdf > 0.0f)) return std::nullopt;
    const Rgb transmittance = transmittance_.at(ctx);
    s.value = transmittance * kInvPi;
    s.weight = transmittance;  // (T / pi) |cos| / (|cos| / pi)
    s.pdf_reverse = std::abs(wo.z) * kInvPi;
    s.lobe = kLobeDiffuse | kLobeTransmission;
    return s;
  }

  uint32_t lobes() const override { return kLobeDiffuse | kLobeTransmission; }
  std::string name() const override { return "diffuse_transmitter"; }

 private:
  TextureParam transmittance_;
};

}  // namespace

BsdfPtr make_diffuse_transmitter(TexturePtr transmittance) {
  return std::make_shared<DiffuseTransmitter>(std::move(transmittance));
}

BsdfPtr make_diffuse_transmitter(const Rgb& transmittance) {
  return make_diffuse_transmitter(make_constant_texture(glm::max(transmittance, Rgb(0.0f))));
}

}  // namespace emlt
