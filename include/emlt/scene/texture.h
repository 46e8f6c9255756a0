#pragma once
// Textures: colours (or scalars) that vary over a surface's (u, v) parametrisation. Every
// material parameter that Mitsuba lets a texture drive (diffuse and specular reflectance,
// roughness, bump height, mask opacity) takes a TexturePtr; a plain colour is a constant
// texture, which the materials recognise and read without a virtual call.
//
// (u, v) convention (Mitsuba 0.6's): v = 0 is the image's top row, u grows to the right,
// and the pattern repeats with period 1. OBJ files are the other way up in v, so the
// loaders flip their `vt` (Mitsuba's default `flipTexCoords`).
#include <concepts>
#include <memory>
#include <optional>
#include <string>

#include "emlt/core/math.h"
#include "emlt/image/image.h"

namespace emlt {

// Mitsuba's uoffset/voffset/uscale/vscale (uvscale sets both scales): uv' = uv * scale +
// offset, applied before the lookup.
struct UvTransform {
  Vec2 scale{1.0f};
  Vec2 offset{0.0f};
  Vec2 apply(const Vec2& uv) const { return uv * scale + offset; }
};

class Texture {
 public:
  virtual ~Texture() = default;
  virtual Rgb eval(const Vec2& uv) const = 0;
  // The lookup at a surface point, where `vertex_color` is the mesh's per-vertex colours
  // interpolated there (black on a surface without them). Only textures that read those
  // colours (reads_vertex_colors()) look at it, so callers that have no surface point may
  // use eval(uv) for every other texture.
  virtual Rgb eval_at(const Vec2& uv, const Rgb& /*vertex_color*/) const { return eval(uv); }
  // Whether eval_at reads the vertex colour (Mitsuba's `vertexcolors`, or a texture
  // wrapping one); such a texture does not vary with uv.
  virtual bool reads_vertex_colors() const { return false; }
  // Scalar readings of the colour, as Mitsuba takes them: the channel mean for
  // roughness, the luminance for bump heights and mask opacity.
  float eval_average(const Vec2& uv) const {
    const Rgb c = eval(uv);
    return (c.x + c.y + c.z) / 3.0f;
  }
  float eval_luminance(const Vec2& uv) const { return luminance(eval(uv)); }
  // The value when the texture does not vary over the surface; nullopt otherwise.
  virtual std::optional<Rgb> constant() const { return std::nullopt; }
  // A uv step small enough to resolve the texture's detail (about one texel), used for
  // finite-difference gradients in bump mapping.
  virtual Vec2 gradient_step() const { return Vec2(1e-3f); }
  virtual std::string name() const = 0;
};

using TexturePtr = std::shared_ptr<const Texture>;

TexturePtr make_constant_texture(const Rgb& value);

// Mitsuba's wrap modes: outside the image a texel repeats, mirrors, clamps to the edge, or
// is 0 or 1 (`zero`/`black`, `one`/`white`).
enum class WrapMode { Repeat, Mirror, Clamp, Zero, One };
// One mode per texture axis (Mitsuba's wrapModeU and wrapModeV); a single mode sets both.
struct TextureWrap {
  WrapMode u = WrapMode::Repeat, v = WrapMode::Repeat;
  TextureWrap() = default;
  TextureWrap(WrapMode both) : u(both), v(both) {}  // NOLINT: a mode is a wrap for both axes
  TextureWrap(WrapMode u_mode, WrapMode v_mode) : u(u_mode), v(v_mode) {}
};

// Bilinear lookup with texel centres at ((i + 0.5) / width, (j + 0.5) / height). The
// image holds linear values.
TexturePtr make_bitmap_texture(Image image, const UvTransform& transform = {},
                               TextureWrap wrap = {}, std::string name = "bitmap");
// Reads the file as read_image does: PNG/JPG decoded by the file's own curve (sRGB, or a
// PNG's gAMA), float formats (EXR, HDR, PFM) linear. A `gamma` given replaces the file's
// curve, as Mitsuba's bitmap `gamma` does (kSrgbGamma, or the exponent: 1 reads the
// stored values linearly). `channel` (PNG and JPEG): one of the file's channels as a grey
// texture, Mitsuba's bitmap `channel` (select_channel; alpha is linear, whatever `gamma`).
// Throws emlt::Error naming the file.
TexturePtr load_bitmap_texture(const std::string& path, std::optional<float> gamma = {},
                               const UvTransform& transform = {}, TextureWrap wrap = {},
                               const std::string& channel = "");
// (A bool would silently become the exponent 0 or 1: say 1.0f or std::nullopt.)
template <std::same_as<bool> Bool>
TexturePtr load_bitmap_texture(const std::string& path, Bool, const UvTransform& = {},
                               TextureWrap = {}) = delete;

// Mitsuba's `vertexcolors`: the mesh's per-vertex colour, interpolated barycentrically at
// the surface point (eval_at); without a surface point (eval), black.
TexturePtr make_vertex_colors_texture();

// Mitsuba's `scale`: the nested texture times a factor.
TexturePtr make_scale_texture(TexturePtr inner, const Rgb& factor);

// Mitsuba's `checkerboard`: color0 on cells where floor(2u) and floor(2v) have the same
// parity, color1 elsewhere (2 x 2 cells per unit square before the uv transform).
TexturePtr make_checkerboard_texture(const Rgb& color0, const Rgb& color1,
                                     const UvTransform& transform = {});

// Mitsuba's `gridtexture`: color1 on lines of half-width `line_width` (in uv units) along
// every whole u and v after the uv transform, color0 between them.
TexturePtr make_grid_texture(const Rgb& color0, const Rgb& color1, float line_width,
                             const UvTransform& transform = {});

}  // namespace emlt
