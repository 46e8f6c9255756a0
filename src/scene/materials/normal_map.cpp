// Mitsuba 0.6's `normalmap`: a texture whose RGB encodes a normal n = 2 rgb - 1 in the
// tangent space of the surface (x along dp/du, z the shading normal), replacing the
// shading normal the nested BSDF sees. Mitsuba 0.6 orients the new frame's s axis along
// dp/du made orthogonal to the new normal. Here the wrapper works in the local frame the
// integrator hands it, whose s axis follows dp/du (is_anisotropic() asks for that) and in
// which dp/du is (1, 0, 0) wherever it is orthogonal to the normal (flat faces, spheres):
// the new frame is then n' = normalize(n), s' = normalize((1, 0, 0) - n' n'.x),
// t' = n' x s', Mitsuba 0.6's frame exactly (and Mitsuba 3's formula). Where dp/du leans
// off an interpolated normal, s' turns about n', which changes only an anisotropic nested
// BSDF.
//
// Mitsuba's BSDF values include the cosine to the perturbed normal, while the integrators
// here multiply by the cosine to the unperturbed one: the value is scaled by
// |cos wi'| / |cos wi| to give Mitsuba's product. That makes it non-reciprocal, so in
// importance transport the adjoint is used (Veach's shading-normal correction: the ratio
// taken on wo's side). As Mitsuba does, a direction wi on the other side of the perturbed
// normal than of the unperturbed one is black.
#include <optional>
#include <utility>

#include "emlt/scene/materials.h"

namespace emlt {
namespace {

class NormalMap final : public Bsdf {
 public:
  NormalMap(BsdfPtr nested, TexturePtr normals)
      : nested_(std::move(nested)), normals_(std::move(normals)) {}

  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    const Frame frame = perturbed(ctx);
    const Vec3 wo_p = frame.to_local(wo), wi_p = frame.to_local(wi);
    if (!(wi.z * wi_p.z > 0.0f) || wo.z == 0.0f) return Rgb(0.0f);
    return nested_->eval(ctx, wo_p, wi_p) * cosine_ratio(ctx, wo, wi, wo_p, wi_p);
  }

  float pdf(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    const Frame frame = perturbed(ctx);
    const Vec3 wo_p = frame.to_local(wo), wi_p = frame.to_local(wi);
    if (!(wi.z * wi_p.z > 0.0f) || wo.z == 0.0f) return 0.0f;
    return nested_->pdf(ctx, wo_p, wi_p);  // a rotation keeps solid angles
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2& u) const override {
    if (wo.z == 0.0f) return std::nullopt;
    const Frame frame = perturbed(ctx);
    const Vec3 wo_p = frame.to_local(wo);
    std::optional<BsdfSample> s = nested_->sample(ctx, wo_p, u_lobe, u);
    if (!s) return std::nullopt;
    const Vec3 wi_p = s->wi;
    s->wi = frame.to_world(wi_p);
    if (!(s->wi.z * wi_p.z > 0.0f)) return std::nullopt;
    // The nested weight is Mitsuba's (f cos' / pdf); only the adjoint differs.
    if (ctx.mode == TransportMode::Importance)
      s->weight *= cosine_ratio(ctx, wo, s->wi, wo_p, wi_p) * std::abs(s->wi.z / wi_p.z);
    s->value = s->weight * (s->pdf / std::abs(s->wi.z));
    if (!is_finite(s->weight) || !is_finite(s->value)) return std::nullopt;
    return s;
  }

  uint32_t lobes() const override { return nested_->lobes(); }
  std::string name() const override { return "normalmap"; }
  // The map's tangent space is dp/du's: the frame must follow it.
  bool is_anisotropic() const override { return true; }

 private:
  Frame perturbed(const BsdfContext& ctx) const {
    const Vec3 n = 2.0f * normals_->eval_at(ctx.uv, ctx.vertex_color) - Vec3(1.0f);
    const float length = glm::length(n);
    if (!(length > 0.0f) || !std::isfinite(length)) return Frame(Vec3(0.0f, 0.0f, 1.0f));
    // Gram-Schmidt of dp/du = (1, 0, 0) against the new normal; t' = n' x s'.
    return Frame(n / length, Vec3(1.0f, 0.0f, 0.0f));
  }

  // |cos wi'| / |cos wi| (radiance), or |cos wo'| / |cos wo| (importance, the adjoint).
  static float cosine_ratio(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi,
                            const Vec3& wo_p, const Vec3& wi_p) {
    return ctx.mode == TransportMode::Importance ? std::abs(wo_p.z / wo.z)
                                                 : std::abs(wi_p.z / wi.z);
  }

  BsdfPtr nested_;
  TexturePtr normals_;
};

}  // namespace

BsdfPtr make_normal_map(BsdfPtr nested, TexturePtr normals) {
  return std::make_shared<NormalMap>(std::move(nested), std::move(normals));
}

}  // namespace emlt
