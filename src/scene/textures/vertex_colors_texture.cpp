// Mitsuba 0.6's `vertexcolors` texture: a passthrough of the colour the surface point
// carries, which the scene interpolates from the mesh's per-vertex colours.
#include "emlt/scene/texture.h"

namespace emlt {
namespace {

class VertexColorsTexture final : public Texture {
 public:
  // A lookup with no surface point behind it (a spot light's projection) has no vertex
  // colour to read.
  Rgb eval(const Vec2&) const override { return Rgb(0.0f); }
  Rgb eval_at(const Vec2&, const Rgb& vertex_color) const override { return vertex_color; }
  bool reads_vertex_colors() const override { return true; }
  std::string name() const override { return "vertexcolors"; }
};

}  // namespace

TexturePtr make_vertex_colors_texture() {
  return std::make_shared<VertexColorsTexture>();
}

}  // namespace emlt
