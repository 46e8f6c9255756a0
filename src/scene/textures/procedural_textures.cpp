// Textures that need no image: constant, scale, checkerboard and grid.
#include <utility>

#include "emlt/scene/texture.h"

namespace emlt {
namespace {

class ConstantTexture final : public Texture {
 public:
  explicit ConstantTexture(const Rgb& value) : value_(value) {}
  Rgb eval(const Vec2&) const override { return value_; }
  std::optional<Rgb> constant() const override { return value_; }
  std::string name() const override { return "constant"; }

 private:
  Rgb value_;
};

class ScaleTexture final : public Texture {
 public:
  ScaleTexture(TexturePtr inner, const Rgb& factor) : inner_(std::move(inner)), factor_(factor) {}
  Rgb eval(const Vec2& uv) const override { return inner_->eval(uv) * factor_; }
  Rgb eval_at(const Vec2& uv, const Rgb& vertex_color) const override {
    return inner_->eval_at(uv, vertex_color) * factor_;
  }
  bool reads_vertex_colors() const override { return inner_->reads_vertex_colors(); }
  std::optional<Rgb> constant() const override {
    if (auto c = inner_->constant()) return *c * factor_;
    return std::nullopt;
  }
  Vec2 gradient_step() const override { return inner_->gradient_step(); }
  std::string name() const override { return "scale(" + inner_->name() + ")"; }

 private:
  TexturePtr inner_;
  Rgb factor_;
};

class CheckerboardTexture final : public Texture {
 public:
  CheckerboardTexture(const Rgb& color0, const Rgb& color1, const UvTransform& transform)
      : color0_(color0), color1_(color1), transform_(transform) {}

  // Mitsuba's cell index truncates towards zero, so the cells either side of u = 0 (or
  // v = 0) share a colour: a band twice as wide, which a negative uvoffset shows.
  Rgb eval(const Vec2& uv) const override {
    const Vec2 p = transform_.apply(uv) * 2.0f;
    const auto parity = [](float x) { return int64_t(x) & 1; };  // & 1: the parity of -3 is 1
    return parity(p.x) == parity(p.y) ? color0_ : color1_;
  }
  Vec2 gradient_step() const override { return Vec2(1e-3f) / glm::max(glm::abs(transform_.scale), Vec2(1e-6f)); }
  std::string name() const override { return "checkerboard"; }

 private:
  Rgb color0_, color1_;
  UvTransform transform_;
};

class GridTexture final : public Texture {
 public:
  GridTexture(const Rgb& color0, const Rgb& color1, float line_width, const UvTransform& transform)
      : color0_(color0), color1_(color1), line_width_(line_width), transform_(transform) {}

  // The distance to the nearest whole u and v, each measured as Mitsuba measures it: the
  // fractional part, less one above a half.
  Rgb eval(const Vec2& uv) const override {
    const Vec2 p = transform_.apply(uv);
    const auto offset = [](float x) {
      const float f = x - std::floor(x);
      return f > 0.5f ? f - 1.0f : f;
    };
    return std::abs(offset(p.x)) < line_width_ || std::abs(offset(p.y)) < line_width_ ? color1_
                                                                                      : color0_;
  }
  Vec2 gradient_step() const override {
    return Vec2(1e-3f) / glm::max(glm::abs(transform_.scale), Vec2(1e-6f));
  }
  std::string name() const override { return "grid"; }

 private:
  Rgb color0_, color1_;
  float line_width_;
  UvTransform transform_;
};

}  // namespace

TexturePtr make_constant_texture(const Rgb& value) {
  return std::make_shared<ConstantTexture>(value);
}

TexturePtr make_scale_texture(TexturePtr inner, const Rgb& factor) {
  return std::make_shared<ScaleTexture>(std::move(inner), factor);
}

TexturePtr make_checkerboard_texture(const Rgb& color0, const Rgb& color1,
                                     const UvTransform& transform) {
  return std::make_shared<CheckerboardTexture>(color0, color1, transform);
}

}  // namespace emlt

namespace emlt {

TexturePtr make_grid_texture(const Rgb& color0, const Rgb& color1, float line_width,
                             const UvTransform& transform) {
  return std::make_shared<GridTexture>(color0, color1, line_width, transform);
}

}  // namespace emlt
