// Mitsuba 0.6 <texture> elements: bitmap, checkerboard, gridtexture, scale, vertexcolors, and
// references to textures declared with an id.
#include <fmt/core.h>

#include <filesystem>

#include "emlt/core/error.h"
#include "src/scene/loaders/loader_common.h"
#include "src/scene/loaders/mitsuba_parser.h"

namespace emlt::mitsuba {

namespace {

// Mitsuba 3's `to_uv`, a <transform> applied to (u, v, 1): the 2D part of the 4x4 matrix
// the transform elements build (its x and y rows, with the translation column). emlt
// scales and offsets uv per axis, so the matrix must have no rotation or shear.
UvTransform mitsuba3_uv_transform(const Document& doc, Properties& props) {
  UvTransform t;
  if (!props.has("to_uv")) return t;
  const pugi::xml_node node = props.node_of("to_uv");
  const Mat4 m = props.get_transform("to_uv");  // glm: m[column][row]
  if (m[1][0] != 0.0f || m[0][1] != 0.0f)
    doc.warn(node,
             "a rotated or sheared 'to_uv' is not supported; only its scale and "
             "translation are applied");
  t.scale = Vec2(m[0][0], m[1][1]);
  t.offset = Vec2(m[3][0], m[3][1]);
  return t;
}

UvTransform uv_transform(const Document& doc, Properties& props) {
  if (doc.mitsuba3()) return mitsuba3_uv_transform(doc, props);
  const float uniform = props.get_float("uvscale", 1.0f);
  UvTransform t;
  t.scale = Vec2(props.get_float("uscale", uniform), props.get_float("vscale", uniform));
  t.offset = Vec2(props.get_float("uoffset", 0.0f), props.get_float("voffset", 0.0f));
  return t;
}

// Mitsuba's wrapMode sets both axes; wrapModeU and wrapModeV override it per axis.
TextureWrap wrap_modes(const Document& doc, pugi::xml_node node, Properties& props) {
  const std::string both = props.get_string("wrapMode", "repeat");
  const auto mode = [&](const std::string& name) {
    const std::string value = props.get_string(name, both);
    if (value == "repeat") return WrapMode::Repeat;
    if (value == "mirror") return WrapMode::Mirror;
    if (value == "clamp") return WrapMode::Clamp;
    if (value == "zero" || value == "black") return WrapMode::Zero;
    if (value == "one" || value == "white") return WrapMode::One;
    doc.fail(node, "unknown wrap mode '" + value +
                       "' (expected repeat, mirror, clamp, zero/black or one/white)");
  };
  const WrapMode u = mode("wrapModeU");
  return TextureWrap(u, mode("wrapModeV"));
}

TexturePtr read_bitmap(const Document& doc, pugi::xml_node node, Properties& props) {
  if (!props.has("filename")) doc.fail(node, "<texture type=\"bitmap\"> needs a 'filename'");
  const std::string file = loader::resolve_path(doc.path(), props.get_string("filename", ""));
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    doc.fail(node, "texture image '" + file + "' not found");
  // Mitsuba's `gamma` replaces the file's own curve (an 8-bit file's sRGB, a PNG's gAMA,
  // a float file's linear): -1 is sRGB, any positive value g the curve v^g. 0, Mitsuba's
  // default, leaves the file's.
  std::optional<float> gamma;
  if (doc.mitsuba3()) {
    // Mitsuba 3 knows two curves: an 8- or 16-bit file is sRGB (a PNG's gAMA chunk is not
    // read) unless `raw` says its values are linear; a float file is linear.
    const bool raw = props.get_boolean("raw", false);
    if (is_stored_image(file)) gamma = raw ? 1.0f : kSrgbGamma;
    // Storage precision and lookup acceleration: the same texels.
    props.ignore({"format", "accel"});
  } else if (props.has("gamma")) {
    const float value = props.get_float("gamma", 0.0f);
    if (value == kSrgbGamma || value > 0.0f)
      gamma = value;
    else if (value != 0.0f)
      doc.fail(node, fmt::format("bitmap gamma {}", value) +
                         " is not a curve (expected -1 for sRGB or a positive exponent)");
  }
  // Filtering quality only: bilinear lookups averaged over many samples per pixel.
  props.ignore({"filterType", "maxAnisotropy", "cache"});
  const TextureWrap wrap = wrap_modes(doc, node, props);
  const UvTransform transform = uv_transform(doc, props);
  std::string channel;
  if (props.has("channel")) {
    channel = props.get_string("channel", "");
    if (!is_stored_image(file)) {
      doc.warn(node, "bitmap 'channel' of a float image is not supported; using the RGB channels",
               Document::Warning::Approximated);
      channel.clear();
    }
  }
  try {
    return load_bitmap_texture(file, gamma, transform, wrap, channel);
  } catch (const Error& e) {
    doc.fail(node, e.what());
  }
}

TexturePtr nested_texture(const Document& doc, pugi::xml_node node, Properties& props,
                          NamedObjects& named) {
  TexturePtr inner;
  for (const std::string& name : props.names_of_kind("texture"))
    if (!inner) inner = props.get_texture(name, Rgb(0.0f), named);
  for (pugi::xml_node child : props.objects()) {
    const std::string kind = child.name();
    if ((kind == "texture" || kind == "ref") && !inner)
      inner = read_texture(doc, child, named);
    else
      doc.warn(child,
               "unsupported element <" + kind + "> inside " + doc.describe(node) + " ignored");
  }
  if (!inner) doc.fail(node, doc.describe(node) + " needs a nested <texture>");
  return inner;
}

// What Mitsuba's `scale` scales: its `value` (a colour), replaced by a nested texture, named
// or not; of several, the last in the file, as Mitsuba adds each in turn in its place.
TexturePtr scaled_texture(const Document& doc, pugi::xml_node node, Properties& props,
                          NamedObjects& named) {
  pugi::xml_node last;
  for (pugi::xml_node child : node.children()) {
    const std::string kind = child.name();
    if (kind == "texture" || kind == "ref") last = child;
  }
  for (const char* kind : {"texture", "ref"})
    for (const std::string& name : props.names_of_kind(kind)) props.ignore({name.c_str()});
  for (pugi::xml_node child : props.objects()) {
    const std::string kind = child.name();
    if (kind != "texture" && kind != "ref")
      doc.warn(child,
               "unsupported element <" + kind + "> inside " + doc.describe(node) + " ignored");
  }
  if (last) {
    if (props.has("value") && !props.used("value")) {
      props.ignore({"value"});
      doc.warn(props.node_of("value"),
               "'value' of a scale texture replaced by its nested texture, as Mitsuba does",
               Document::Warning::Note);
    }
    return read_texture(doc, last, named);
  }
  if (!props.has("value"))
    doc.fail(node, doc.describe(node) + " needs a nested <texture> or a 'value'");
  return make_constant_texture(props.get_color("value", Rgb(0.0f)));
}

}  // namespace

TexturePtr read_texture(const Document& doc, pugi::xml_node node, NamedObjects& named) {
  if (std::string(node.name()) == "ref") {
    const std::string id = doc.attribute(node, "id");
    auto it = named.textures.find(id);
    if (it == named.textures.end()) doc.fail(node, "unknown texture id '" + id + "'");
    return it->second;
  }
  const std::string type = doc.attribute(node, "type");
  Properties props(doc, node);
  TexturePtr texture;
  if (type == "bitmap") {
    texture = read_bitmap(doc, node, props);
  } else if (type == "checkerboard") {
    const Rgb color0 = props.get_color("color0", Rgb(0.4f));
    const Rgb color1 = props.get_color("color1", Rgb(0.2f));
    texture = make_checkerboard_texture(color0, color1, uv_transform(doc, props));
  } else if (type == "gridtexture") {
    const Rgb color0 = props.get_color("color0", Rgb(0.2f));
    const Rgb color1 = props.get_color("color1", Rgb(0.4f));
    const float line_width = props.get_float("lineWidth", 0.01f);
    texture = make_grid_texture(color0, color1, line_width, uv_transform(doc, props));
  } else if (type == "vertexcolors" && !doc.mitsuba3()) {
    // No parameters: the colours come from the mesh (Mitsuba 3 has no such plugin).
    texture = make_vertex_colors_texture();
  } else if (type == "scale") {
    const Rgb factor = props.get_color("scale", Rgb(1.0f));
    TexturePtr inner = doc.mitsuba3() ? nested_texture(doc, node, props, named)
                                      : scaled_texture(doc, node, props, named);
    texture = make_scale_texture(inner, factor);
  } else {
    doc.warn(node, "unsupported texture type '" + type + "'; using a constant 0.5");
    texture = make_constant_texture(Rgb(0.5f));
    if (doc.has_attribute(node, "id")) named.textures[doc.attribute(node, "id")] = texture;
    return texture;  // its parameters mean nothing here; one warning is enough
  }
  props.warn_unused();
  if (doc.has_attribute(node, "id")) named.textures[doc.attribute(node, "id")] = texture;
  return texture;
}

TexturePtr Properties::get_texture(const std::string& name, const Rgb& fallback,
                                   NamedObjects& named) {
  const std::string kind = kind_of(name);
  if (kind != "texture" && kind != "ref") return make_constant_texture(get_color(name, fallback));
  return read_texture(doc_, take(name, {"texture", "ref"}), named);
}

}  // namespace emlt::mitsuba
