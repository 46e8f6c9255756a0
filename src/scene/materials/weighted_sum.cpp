// sum_i w_i f_i, sampled by choosing a part in proportion to its weight. A direction drawn
// from a smooth lobe is weighed by every part's value and density (one-sample MIS with the
// balance heuristic over the parts, as Mitsuba's mixture does); a delta direction by its own
// part alone, since no other part can draw that exact direction.
#include "src/scene/materials/weighted_sum.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace emlt {
namespace {

class WeightedSum final : public Bsdf {
 public:
  WeightedSum(std::vector<BsdfPtr> parts, std::vector<float> weights, TexturePtr blend,
              std::string name)
      : parts_(std::move(parts)),
        weights_(std::move(weights)),
        blend_(std::move(blend)),
        name_(std::move(name)) {
    for (const BsdfPtr& part : parts_) {
      lobes_ |= part->lobes();
      anisotropic_ |= part->is_anisotropic();
    }
    if (blend_) {
      if (auto c = blend_->constant()) {
        constant_blend_ = blend_fraction(*c);
        blend_.reset();
      }
    }
    blend_reads_vertex_colors_ = blend_ && blend_->reads_vertex_colors();
    for (float w : weights_) total_ += w;
  }

  Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    Rgb sum(0.0f);
    for (size_t i = 0; i < parts_.size(); ++i) {
      const float w = weight(ctx, i);
      if (w > 0.0f) sum += w * parts_[i]->eval(ctx, wo, wi);
    }
    return sum;
  }

  float pdf(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const override {
    const float total = total_weight();
    float sum = 0.0f;
    for (size_t i = 0; i < parts_.size(); ++i) {
      const float w = weight(ctx, i);
      if (w > 0.0f) sum += w / total * parts_[i]->pdf(ctx, wo, wi);
    }
    return sum;
  }

  std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                   const Vec2& u) const override {
    const float total = total_weight();
    if (!(total > 0.0f)) return std::nullopt;
    // The part whose share of [0, 1) holds u_lobe; u_lobe rescaled within that share is
    // the part's own lobe choice.
    size_t chosen = parts_.size();
    float below = 0.0f, probability = 0.0f;
    for (size_t i = 0; i < parts_.size(); ++i) {
      const float p = weight(ctx, i) / total;
      if (p <= 0.0f) continue;
      chosen = i;
      probability = p;
      if (u_lobe < below + p) break;
      below += p;
    }
    if (chosen == parts_.size()) return std::nullopt;
    const float u_part = std::min((u_lobe - below) / probability, 0x1.fffffep-1f);
    std::optional<BsdfSample> s = parts_[chosen]->sample(ctx, wo, std::max(u_part, 0.0f), u);
    if (!s) return std::nullopt;
    const float w = weight(ctx, chosen);
    if (s->is_delta()) {
      s->value *= w;
      s->pdf *= probability;
      s->pdf_reverse *= probability;
    } else {
      s->value = eval(ctx, wo, s->wi);
      s->pdf = pdf(ctx, wo, s->wi);
      s->pdf_reverse = pdf(ctx, s->wi, wo);
    }
    if (!(s->pdf > 0.0f)) return std::nullopt;
    s->weight = s->value * (std::abs(s->wi.z) / s->pdf);
    if (!is_finite(s->weight)) return std::nullopt;
    return s;
  }

  uint32_t lobes() const override { return lobes_; }
  bool is_anisotropic() const override { return anisotropic_; }
  std::string name() const override {
    std::string text = name_ + "(";
    for (size_t i = 0; i < parts_.size(); ++i) text += (i ? ", " : "") + parts_[i]->name();
    return text + ")";
  }

 private:
  static float blend_fraction(const Rgb& value) {
    return glm::clamp((value.x + value.y + value.z) / 3.0f, 0.0f, 1.0f);
  }

  float blend_at(const BsdfContext& ctx) const {
    if (!blend_) return constant_blend_;
    return blend_fraction(blend_reads_vertex_colors_ ? blend_->eval_at(ctx.uv, ctx.vertex_color)
                                                     : blend_->eval(ctx.uv));
  }

  float weight(const BsdfContext& ctx, size_t part) const {
    if (!is_blend()) return weights_[part];
    const float w = blend_at(ctx);
    return part == 0 ? 1.0f - w : w;
  }

  float total_weight() const { return is_blend() ? 1.0f : total_; }
  bool is_blend() const { return weights_.empty(); }

  std::vector<BsdfPtr> parts_;
  std::vector<float> weights_;  // empty for a blended pair
  TexturePtr blend_;            // a blended pair's varying weight; null when constant
  bool blend_reads_vertex_colors_ = false;
  float constant_blend_ = 0.5f;
  float total_ = 0.0f;
  uint32_t lobes_ = kLobeNone;
  bool anisotropic_ = false;
  std::string name_;
};

}  // namespace

BsdfPtr make_weighted_sum(std::vector<BsdfPtr> parts, std::vector<float> weights,
                          std::string name) {
  return std::make_shared<WeightedSum>(std::move(parts), std::move(weights), nullptr,
                                       std::move(name));
}

BsdfPtr make_blended_pair(TexturePtr weight, BsdfPtr first, BsdfPtr second, std::string name) {
  return std::make_shared<WeightedSum>(std::vector<BsdfPtr>{std::move(first), std::move(second)},
                                       std::vector<float>{}, std::move(weight), std::move(name));
}

}  // namespace emlt
