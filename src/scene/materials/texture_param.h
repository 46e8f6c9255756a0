#pragma once
// A material parameter given by a texture (internal to the engine). Constant textures are
// read once at construction, so plain-coloured materials pay no virtual call per query.
#include <utility>

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
  bool is_constant() const { return is_constant_; }
  const Rgb& constant_value() const { return constant_; }  // meaningful when is_constant()
  const TexturePtr& texture() const { return texture_; }

 private:
  TexturePtr texture_;
  Rgb constant_{0.0f};
  bool is_constant_ = false;
};

}  // namespace emlt
