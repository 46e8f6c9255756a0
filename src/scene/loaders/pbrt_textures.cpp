// pbrt-v4's colours and textures: rgb, spectrum and blackbody parameters as linear RGB;
// Texture "imagemap", "checkerboard", "scale", "mix" and "constant".
//
// pbrt-v4 renders spectrally: an RGB reflectance becomes a smooth spectrum whose colour
// under a white light is that RGB again, and an emitter's spectrum is normalised to unit
// luminance (scale /= SpectrumToPhotometric). An RGB renderer reads rgb values as they are;
// sampled and black-body spectra are converted to RGB (approximated loudly).
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <filesystem>

#include "emlt/image/image.h"
#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/spectrum.h"
#include "src/scene/loaders/loader_common.h"
#include "src/scene/loaders/pbrt_reader.h"

namespace emlt::pbrt {

Rgb Reader::color(const Params& params, const std::string& name, const Rgb& fallback) {
  const Param* p = params.get(name);
  if (!p) return fallback;
  const Where at{p->file, p->line};
  if (p->type == "float") {
    if (p->numbers.size() != 1) Params::fail(*p, "expected one value");
    return Rgb(float(p->numbers[0]));
  }
  if (p->type == "rgb") {
    if (p->numbers.size() != 3) Params::fail(*p, "expected three values");
    const Rgb c(float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2]));
    if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) Params::fail(*p, "negative colour");
    return c;
  }
  if (p->type == "blackbody") {
    if (p->numbers.size() != 1 || !(p->numbers[0] > 0.0))
      Params::fail(*p, "expected one positive temperature (kelvin)");
    const Rgb rgb = spectrum::blackbody_to_rgb(p->numbers[0]);
    const float y = luminance(rgb);
    if (!(y > 0.0f)) Params::fail(*p, "a black body this cold emits no visible light");
    warn(at,
         p->quoted() + fmt::format(": the black body of {:g} K as RGB of unit luminance "
                                   "(pbrt renders its spectrum)",
                                   p->numbers[0]),
         Divergence::Kind::Approximated);
    return rgb / y;
  }
  if (p->type == "spectrum") {
    if (!p->numbers.empty()) {
      if (p->numbers.size() % 2 != 0 || p->numbers.size() < 4)
        Params::fail(*p, "expected wavelength-value pairs");
      std::vector<float> lambda, value;
      for (size_t i = 0; i < p->numbers.size(); i += 2) {
        lambda.push_back(float(p->numbers[i]));
        value.push_back(float(p->numbers[i + 1]));
        if (i > 0 && !(lambda.back() > lambda[lambda.size() - 2]))
          Params::fail(*p, "wavelengths must increase");
      }
      warn(at, p->quoted() + ": a sampled spectrum as RGB (CIE 1931; pbrt renders it spectrally)",
           Divergence::Kind::Approximated);
      return spectrum::sampled_to_rgb(spectrum::make_piecewise_linear(lambda, value));
    }
    if (p->strings.size() != 1) Params::fail(*p, "expected one named spectrum");
    const std::string& named = p->strings[0];
    // The sRGB white is D65's colour: pbrt's default light spectrum renders as (1, 1, 1).
    if (named == "stdillum-D65") return Rgb(1.0f);
    warn(at, p->quoted() + " \"" + named + "\": this named spectrum is not supported; (" +
                 fmt::format("{:g}, {:g}, {:g}", fallback.x, fallback.y, fallback.z) + ") is used");
    return fallback;
  }
  Params::fail(*p, "expected a colour (rgb, spectrum or blackbody)");
}

TexturePtr Reader::texture(const Params& params, const std::string& name, const Rgb& fallback,
                           bool float_texture) {
  const Param* p = params.get(name);
  if (!p) return make_constant_texture(fallback);
  if (p->type == "texture") {
    if (p->strings.size() != 1) Params::fail(*p, "expected one texture name");
    auto& table = float_texture ? float_textures_ : color_textures_;
    const auto it = table.find(p->strings[0]);
    if (it == table.end())
      Params::fail(*p, std::string("no ") + (float_texture ? "float" : "spectrum") +
                           " texture named \"" + p->strings[0] + "\"");
    return it->second;
  }
  if (float_texture && p->type != "float") Params::fail(*p, "expected a float or a texture");
  return make_constant_texture(color(params, name, fallback));
}

std::optional<float> Reader::constant_float(const Params& params, const std::string& name,
                                            float fallback) {
  const TexturePtr t = texture(params, name, Rgb(fallback), true);
  const std::optional<Rgb> c = t->constant();
  if (!c) return std::nullopt;
  return c->x;
}

void Reader::texture_declaration(const Where& at, const std::string& name, const std::string& kind,
                                 const std::string& type, const Params& params) {
  const bool float_texture = kind == "float";
  if (!float_texture && kind != "spectrum" && kind != "color")
    fail(at, "Texture \"" + name + "\": unknown texture kind '" + kind + "' (float or spectrum)");
  const std::string what = "Texture \"" + name + "\" (\"" + type + "\")";
  const Rgb one(1.0f), zero(0.0f);
  // The uv mapping: pbrt's (s, t) = (su u + du, sv v + dv).
  const std::string mapping = params.get_string("mapping", "uv");
  if (mapping != "uv")
    warn(at, what + ": mapping \"" + mapping + "\" is not supported; \"uv\" is used");
  const float su = params.get_float("uscale", 1.0f), sv = params.get_float("vscale", 1.0f),
              du = params.get_float("udelta", 0.0f), dv = params.get_float("vdelta", 0.0f);
  for (const char* n : {"v1", "v2"}) params.ignore(n);

  TexturePtr result;
  if (type == "constant") {
    result = texture(params, "value", one, float_texture);
  } else if (type == "imagemap") {
    const std::string file_name = params.get_string("filename", "");
    if (file_name.empty()) fail(at, what + " needs 'string filename'");
    const std::string file = resolve(at, file_name);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
      fail(at, what + ": image '" + file_name + "' not found");
    // pbrt looks an image up at (s, 1 - t), row 0 at the top; emlt's v = 0 is the top row.
    UvTransform uv;
    uv.scale = Vec2(su, -sv);
    uv.offset = Vec2(du, 1.0f - dv);
    std::optional<float> gamma;
    // pbrt-v4's default: sRGB for a PNG file, linear for any other (a JPEG's 8-bit values
    // too, unless the file says "sRGB").
    std::string extension = std::filesystem::path(file).extension().string();
    for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
    const std::string encoding =
        params.get_string("encoding", extension == ".png" ? "sRGB" : "linear");
    if (is_stored_image(file)) {
      if (encoding == "linear")
        gamma = 1.0f;
      else if (encoding == "sRGB")
        gamma = kSrgbGamma;
      else if (encoding.rfind("gamma ", 0) == 0) {
        const float g = std::strtof(encoding.c_str() + 6, nullptr);
        if (!(g > 0.0f)) fail(at, what + ": bad encoding \"" + encoding + "\"");
        gamma = g;
      } else {
        fail(at, what + ": unknown encoding \"" + encoding + "\" (sRGB, linear, gamma G)");
      }
    }
    const std::string wrap_name = params.get_string("wrap", "repeat");
    WrapMode wrap = WrapMode::Repeat;
    if (wrap_name == "black")
      wrap = WrapMode::Zero;
    else if (wrap_name == "clamp")
      wrap = WrapMode::Clamp;
    else if (wrap_name != "repeat")
      warn(at, what + ": wrap \"" + wrap_name + "\" is not supported; \"repeat\" is used");
    result = load_bitmap_texture(file, gamma, uv, TextureWrap(wrap));
    if (params.get_bool("invert", false))
      warn(at, what + ": 'invert' is not supported; the image is used as it is");
    const float scale = params.get_float("scale", 1.0f);
    if (scale != 1.0f) result = make_scale_texture(result, Rgb(scale));
    const std::string filter = params.get_string("filter", "bilinear");
    if (filter != "bilinear" && filter != "point")
      note(at, what + ": filter \"" + filter +
                   "\" read as bilinear (the converged image "
                   "differs only where the texture is minified)");
    params.ignore("maxanisotropy");
  } else if (type == "checkerboard") {
    const int dimension = params.get_int("dimension", 2);
    if (dimension != 2) warn(at, what + ": a 3D checkerboard is not supported; the 2D one is used");
    const TexturePtr a = texture(params, "tex1", one, float_texture),
                     b = texture(params, "tex2", zero, float_texture);
    if (!a->constant() || !b->constant())
      warn(at, what + ": textured checks are not supported; their values at uv (0, 0) are used");
    // pbrt: tex1 where floor(s) + floor(t) is even. emlt's checkerboard has two cells per
    // unit of its coordinate: it reads (s, t) / 2.
    UvTransform uv;
    uv.scale = Vec2(su, sv) * 0.5f;
    uv.offset = Vec2(du, dv) * 0.5f;
    result = make_checkerboard_texture(a->eval(Vec2(0.0f)), b->eval(Vec2(0.0f)), uv);
  } else if (type == "scale") {
    TexturePtr tex = texture(params, "tex", one, float_texture);
    TexturePtr scale = texture(params, "scale", one, true);
    if (const auto s = scale->constant())
      result = make_scale_texture(tex, *s);
    else if (const auto t = tex->constant())
      result = make_scale_texture(scale, *t);
    else {
      warn(at, what + ": the product of two varying textures is not supported; 'tex' is used");
      result = tex;
    }
  } else if (type == "mix") {
    const TexturePtr a = texture(params, "tex1", zero, float_texture),
                     b = texture(params, "tex2", one, float_texture);
    const TexturePtr amount = texture(params, "amount", Rgb(0.5f), true);
    if (a->constant() && b->constant() && amount->constant()) {
      const float t = amount->constant()->x;
      result = make_constant_texture((1.0f - t) * *a->constant() + t * *b->constant());
    } else {
      warn(at, what + ": a mix of varying textures is not supported; 'tex1' is used");
      result = a;
    }
  } else {
    for (const Param* p : params.unused()) p->used = true;
    warn(at, what + ": texture type '" + type + "' is not supported; a constant 0.5 is used");
    result = make_constant_texture(Rgb(0.5f));
  }
  report_unused(params, what);
  (float_texture ? float_textures_ : color_textures_)[name] = result;
}

}  // namespace emlt::pbrt
