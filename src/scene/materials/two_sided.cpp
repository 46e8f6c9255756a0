// Makes a one-sided BSDF behave identically on the back face by mirroring the local frame
// through the tangent plane whenever wo is below it (Mitsuba's `twosided`).
#include <utility>

#include "emlt/scene/materials.h"

namespace emlt {
namespace {

Vec3 flip_z(const Vec3& w) { return {w.x, w.y, -w.z}; }

class TwoSided final : public Bsdf {
 public:
  explicit TwoSided(BsdfPtr inner) : inner_(std::move(inner)) {}

  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    return wo.z < 0.0f ? inner_->eval(ctx, flip_z(wo), flip_z(wi)) : inner_->eval(ctx, wo, wi);
  }

  float pdf(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    return wo.z < 0.0f ? inner_->pdf(ctx, flip_z(wo), flip_z(wi)) : inner_->pdf(ctx, wo, wi);
  }

  // pdf_reverse needs no fix-up: wi lies on wo's side for a one-sided inner BSDF, so the
  // reverse query flips exactly as the forward one did.
  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2& u) const override {
    if (wo.z >= 0.0f) return inner_->sample(ctx, wo, u_lobe, u);
    auto s = inner_->sample(ctx, flip_z(wo), u_lobe, u);
    if (s) s->wi = flip_z(s->wi);
    return s;
  }

  uint32_t lobes() const override { return inner_->lobes(); }
  bool is_anisotropic() const override { return inner_->is_anisotropic(); }
  std::string name() const override { return "two_sided(" + inner_->name() + ")"; }

 private:
  BsdfPtr inner_;
};

}  // namespace

BsdfPtr make_two_sided(BsdfPtr inner) { return std::make_shared<TwoSided>(std::move(inner)); }

}  // namespace emlt
