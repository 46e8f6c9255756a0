#pragma once
// A material parameter given by a texture (internal to the engine). Constant textures are
// read once at construction, so plain-coloured materials pay no virtual call per query.
#include <utility>

#include "emlt/scene/bsdf.h"
#include "emlt/scene/texture.h"

namespace emlt {

class TextureParam {
 public:
  explicit TextureParam(TexturePtr texture) : texture_(std::move(texture)) {
    if (!texture_) texture_ = make_constant_texture(Rgb(0.0f));
    if (auto c = texture_->constant()) {
      constant_ = glm::max(*c, Rgb(0.0f));
      is_constant_ = true;
    }
    reads_vertex_colors_ = texture_->reads_vertex_colors();
  }
  explicit TextureParam(const Rgb& value) : TextureParam(make_constant_texture(value)) {}

  // Negative texels are clamped: no parameter driven this way may go below zero.
  Rgb at(const Vec2& uv) const {
    return is_constant_ ? constant_ : glm::max(texture_->eval(uv), Rgb(0.0f));
  }
  float average_at(const Vec2& uv) const {
    const Rgb c = at(uv);
    return (c.x + c.y + c.z) / 3.0f;
  }
  // At a surface point: the same, except that a texture of vertex colours reads the
  // point's colour (the test keeps other textures to the one virtual call of at(uv)).
  Rgb at(const BsdfContext& ctx) const {
    if (!reads_vertex_colors_) return at(ctx.uv);
    return glm::max(texture_->eval_at(ctx.uv, ctx.vertex_color), Rgb(0.0f));
  }
  float average_at(const BsdfContext& ctx) const {
    const Rgb c = at(ctx);
    return (c.x + c.y + c.z) / 3.0f;
  }
  bool is_constant() const { return is_constant_; }
  const Rgb& constant_value() const { return constant_; }  // meaningful when is_constant()
  const TexturePtr& texture() const { return texture_; }

 private:
  TexturePtr texture_;
  Rgb constant_{0.0f};
  bool is_constant_ = false;
  bool reads_vertex_colors_ = false;
};

}  // namespace emlt
