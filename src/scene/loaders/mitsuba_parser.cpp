#include "src/scene/loaders/mitsuba_parser.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>

#include "emlt/core/error.h"
#include "emlt/scene/shape_builders.h"
#include "emlt/scene/spectrum.h"
#include "src/scene/loaders/loader_common.h"
#include "src/scene/loaders/mitsuba3_names.h"

namespace emlt::mitsuba {

namespace {

float srgb_to_linear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

bool is_identifier_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// The up vector Mitsuba's <lookat> takes when the file gives none (or a zero one): its
// coordinateSystem()'s second axis for the viewing direction, so that a panel placed facing
// straight up, where (0, 1, 0) would be degenerate, still has a frame, and a camera without
// `up` turns about its axis exactly as Mitsuba's does.
Vec3 mitsuba_default_up(const Vec3& origin, const Vec3& target) {
  const Vec3 a = glm::normalize(target - origin);
  const Vec3 c = std::abs(a.x) > std::abs(a.y)
                     ? Vec3(a.z, 0.0f, -a.x) / std::sqrt(a.x * a.x + a.z * a.z)
                     : Vec3(0.0f, a.z, -a.y) / std::sqrt(a.y * a.y + a.z * a.z);
  return glm::cross(c, a);
}

}  // namespace

Document::Document(std::string path, const SceneDefines& defines,
                   std::vector<std::string>& warnings, std::vector<Divergence>& divergences)
    : path_(std::move(path)), defines_(defines), warnings_(warnings), divergences_(divergences) {
  text_ = loader::read_text_file(path_);
  line_starts_.push_back(0);
  for (size_t i = 0; i < text_.size(); ++i)
    if (text_[i] == '\n') line_starts_.push_back(i + 1);
  const pugi::xml_parse_result result = doc_.load_buffer(text_.data(), text_.size());
  if (!result) {
    const auto it =
        std::upper_bound(line_starts_.begin(), line_starts_.end(), size_t(result.offset));
    throw file_error(path_, "malformed XML at line " + std::to_string(it - line_starts_.begin()) +
                                ": " + result.description());
  }
  if (!scene()) throw file_error(path_, "not a Mitsuba scene (no <scene> root element)");
  mitsuba3_ = is_mitsuba3_version(scene().attribute("version").as_string());
  if (mitsuba3_) check_mitsuba3_plugins(scene());
}

int Document::line(pugi::xml_node node) const {
  const ptrdiff_t offset = node.offset_debug();
  if (offset < 0) return 0;
  const auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), size_t(offset));
  return int(it - line_starts_.begin());
}

std::string Document::attribute(pugi::xml_node node, const char* name) const {
  const std::string raw = node.attribute(name).as_string();
  std::string out;
  for (size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] != '$' || i + 1 >= raw.size() || !is_identifier_char(raw[i + 1])) {
      out += raw[i];
      continue;
    }
    size_t end = i + 1;
    while (end < raw.size() && is_identifier_char(raw[end])) ++end;
    const std::string parameter = raw.substr(i + 1, end - i - 1);
    if (auto it = defines_.find(parameter); it != defines_.end()) {
      out += it->second;
    } else if (auto def = defaults_.find(parameter); def != defaults_.end()) {
      out += def->second;
    } else {
      fail(node, "parameter $" + parameter + " has no value (add <default name=\"" + parameter +
                     "\" value=...> or -D " + parameter + "=...)");
    }
    i = end - 1;
  }
  return out;
}

std::string Document::describe(pugi::xml_node node) const {
  // Built with += throughout: GCC 12 warns falsely (-Wrestrict) on "literal" + string&&.
  std::string text = "<";
  text += node.name();
  for (const char* key : {"type", "name"}) {
    if (!node.attribute(key)) continue;
    text += ' ';
    text += key;
    text += "=\"";
    text += node.attribute(key).as_string();
    text += '"';
    break;
  }
  text += '>';
  return text;
}

void Document::fail(pugi::xml_node node, const std::string& problem) const {
  throw file_error(path_, "line " + std::to_string(line(node)) + ": " + problem);
}

void Document::warn(pugi::xml_node node, const std::string& message, Warning kind) const {
  warnings_.push_back(path_ + ": line " + std::to_string(line(node)) + ": " + message);
  if (kind != Warning::Note)
    divergences_.push_back({kind == Warning::Approximated ? Divergence::Kind::Approximated
                                                          : Divergence::Kind::Unsupported,
                            warnings_.back()});
}

float Document::to_float(pugi::xml_node node, const std::string& text) const {
  const char* begin = text.c_str();
  char* end = nullptr;
  const float value = std::strtof(begin, &end);
  while (end && std::isspace(static_cast<unsigned char>(*end))) ++end;
  if (end == begin || (end && *end != '\0')) fail(node, "'" + text + "' is not a number");
  if (!std::isfinite(value)) fail(node, "'" + text + "' is not a finite number");
  return value;
}

std::vector<float> Document::to_floats(pugi::xml_node node, const std::string& text) const {
  std::vector<float> values;
  std::string token;
  for (size_t i = 0; i <= text.size(); ++i) {
    const char c = i < text.size() ? text[i] : ' ';
    if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
      if (!token.empty()) values.push_back(to_float(node, token));
      token.clear();
    } else {
      token += c;
    }
  }
  return values;
}

// ---------------------------------------------------------------------------------------

Properties::Properties(const Document& doc, pugi::xml_node owner) : doc_(doc), owner_(owner) {
  static const std::set<std::string> kValueKinds = {"float", "integer", "boolean",   "string",
                                                    "rgb",   "srgb",    "spectrum",  "blackbody",
                                                    "point", "vector",  "transform", "texture"};
  for (pugi::xml_node child : owner.children()) {
    if (child.type() != pugi::node_element) continue;
    const std::string kind = child.name();
    // A <ref> with a name passes a declared object as a parameter (a texture, mostly).
    if ((kValueKinds.count(kind) || kind == "ref") && child.attribute("name")) {
      const std::string spelled = child.attribute("name").as_string();
      std::string name = spelled;
      if (doc_.mitsuba3()) {
        name = mitsuba3_key(owner.name(), owner.attribute("type").as_string(), spelled);
        if (name.empty()) name = "mitsuba3:" + spelled;
      }
      if (values_.count(name))
        doc_.warn(child, "parameter '" + spelled + "' given twice; the last wins",
                  Document::Warning::Note);
      values_[name] = child;
    } else {
      objects_.push_back(child);
    }
  }
}

pugi::xml_node Properties::take(const std::string& name, std::initializer_list<const char*> kinds) {
  auto it = values_.find(name);
  if (it == values_.end()) return {};
  used_.insert(name);
  for (const char* kind : kinds)
    if (std::string(it->second.name()) == kind) return it->second;
  doc_.fail(it->second, "parameter '" + spelled(name) + "' of " + doc_.describe(owner_) +
                            " cannot be a <" + it->second.name() + ">");
}

float Properties::get_float(const std::string& name, float fallback) {
  const pugi::xml_node node = take(name, {"float", "integer"});
  return node ? doc_.to_float(node, doc_.attribute(node, "value")) : fallback;
}

int Properties::get_integer(const std::string& name, int fallback) {
  const pugi::xml_node node = take(name, {"integer"});
  if (!node) return fallback;
  const std::string text = doc_.attribute(node, "value");
  doc_.to_float(node, text);  // refuses what is not a finite number, in its words
  // The value itself in double precision, which holds every int exactly: single precision
  // rounds 16777217 to 16777216, which a range check would then let through.
  const double value = std::strtod(text.c_str(), nullptr);
  if (value != std::floor(value)) doc_.fail(node, "'" + spelled(name) + "' must be an integer");
  // Converting a double beyond int's range is undefined.
  if (!(std::abs(value) < 2147483648.0))
    doc_.fail(node, "'" + spelled(name) + "' must be an integer within +-2^31 (about 2.1 billion)");
  return int(value);
}

float Properties::get_float(const std::string& name, float fallback,
                            const loader::RealRange& range) {
  const float value = get_float(name, fallback);
  if (!range.contains(value)) out_of_range(name, range.words);
  return value;
}

int Properties::get_integer(const std::string& name, int fallback,
                            const loader::IntegerRange& range) {
  const int value = get_integer(name, fallback);
  if (!range.contains(value)) out_of_range(name, range.words);
  return value;
}

void Properties::out_of_range(const std::string& name, const char* words) const {
  const pugi::xml_node node = node_of(name);
  doc_.fail(node,
            "'" + spelled(name) + "' " + loader::refusal(words, doc_.attribute(node, "value")));
}

std::string Properties::spelled(const std::string& name) const {
  const auto it = values_.find(name);
  return it == values_.end() ? name : it->second.attribute("name").as_string();
}

pugi::xml_node Properties::node_of(const std::string& name) const {
  const auto it = values_.find(name);
  return it == values_.end() ? owner_ : it->second;
}

bool Properties::get_boolean(const std::string& name, bool fallback) {
  const pugi::xml_node node = take(name, {"boolean"});
  if (!node) return fallback;
  const std::string value = doc_.attribute(node, "value");
  if (value == "true") return true;
  if (value == "false") return false;
  doc_.fail(node, "'" + spelled(name) + "' must be true or false, not '" + value + "'");
}

std::string Properties::get_string(const std::string& name, const std::string& fallback) {
  const pugi::xml_node node = take(name, {"string"});
  return node ? doc_.attribute(node, "value") : fallback;
}

Rgb Properties::get_color(const std::string& name, const Rgb& fallback) {
  const pugi::xml_node node =
      take(name, {"rgb", "srgb", "spectrum", "float", "blackbody", "texture"});
  if (!node) return fallback;
  const std::string kind = node.name();
  if (kind == "texture") {
    doc_.warn(node, "<texture> for '" + name + "' is not supported; using the default value");
    return fallback;
  }
  // Every form means the linear RGB triple Mitsuba 0.6's RGB-mode build would load
  // (src/librender/scenehandler.cpp; the conversions are described in spectrum.h).
  // Errors of the spectrum module are reported against this element's line.
  auto convert = [&](auto&& conversion) -> Rgb {
    Rgb rgb(0.0f);
    try {
      rgb = conversion();
    } catch (const std::exception& e) {
      doc_.fail(node, e.what());
    }
    // Finite inputs can still overflow (a blackbody scaled by 1e38): refused here, at the
    // element's line, rather than as an emitter's or material's NaN much later.
    if (!is_finite(rgb)) doc_.fail(node, "'" + name + "' gives a NaN or infinite colour");
    return rgb;
  };
  if (doc_.mitsuba3()) mitsuba3_colour_forms(node);
  if (kind == "blackbody") {
    // Temperature in kelvin, with an optional trailing 'K'.
    std::string temperature = doc_.attribute(node, "temperature");
    while (!temperature.empty() && std::isspace(static_cast<unsigned char>(temperature.back())))
      temperature.pop_back();
    if (!temperature.empty() && std::toupper(static_cast<unsigned char>(temperature.back())) == 'K')
      temperature.pop_back();
    const float kelvin = doc_.to_float(node, temperature);
    const float scale = doc_.has_attribute(node, "scale")
                            ? doc_.to_float(node, doc_.attribute(node, "scale"))
                            : 1.0f;
    return convert([&] { return spectrum::blackbody_to_rgb(kelvin, scale); });
  }
  // `intent` (reflectance or illuminant) only picks how Mitsuba's spectral builds invent a
  // spectrum for an RGB value; in RGB mode it changes nothing, but it is checked as there.
  if (doc_.has_attribute(node, "intent")) {
    std::string intent = doc_.attribute(node, "intent");
    for (char& c : intent) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (intent != "reflectance" && intent != "illuminant")
      doc_.fail(node, "invalid intent '" + intent + "' (reflectance or illuminant)");
  }
  if (kind == "spectrum") {
    const bool has_value = doc_.has_attribute(node, "value");
    if (has_value == doc_.has_attribute(node, "filename"))
      doc_.fail(node, "<spectrum> needs one of 'value' and 'filename'");
    if (!has_value) {
      if (doc_.has_attribute(node, "intent"))
        doc_.fail(node, "<spectrum filename=...> takes no 'intent'");
      const std::string file = loader::resolve_path(doc_.path(), doc_.attribute(node, "filename"));
      return convert([&] { return spectrum::sampled_to_rgb(spectrum::read_spd(file)); });
    }
  }
  const std::string text = doc_.attribute(node, "value");
  std::vector<std::string> tokens;  // split at commas and white space, as Mitsuba does
  {
    std::string token;
    for (size_t i = 0; i <= text.size(); ++i) {
      const char c = i < text.size() ? text[i] : ' ';
      if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
        if (!token.empty()) tokens.push_back(token);
        token.clear();
      } else {
        token += c;
      }
    }
  }
  if (kind == "spectrum" && !tokens.empty() &&
      (tokens.size() > 1 || tokens[0].find(':') != std::string::npos)) {
    if (doc_.has_attribute(node, "intent"))
      doc_.fail(node, "'intent' is only allowed with a single-valued <spectrum>");
    if (tokens[0].find(':') != std::string::npos) {
      // Wavelength:value pairs: a measured spectrum, piecewise linear.
      std::vector<float> wavelengths, values;
      for (const std::string& pair : tokens) {
        const size_t colon = pair.find(':');
        if (colon == std::string::npos || colon == 0 || colon + 1 == pair.size() ||
            pair.find(':', colon + 1) != std::string::npos)
          doc_.fail(node, "'" + pair + "' is not a wavelength:value pair");
        wavelengths.push_back(doc_.to_float(node, pair.substr(0, colon)));
        values.push_back(doc_.to_float(node, pair.substr(colon + 1)));
      }
      return convert([&] {
        return spectrum::sampled_to_rgb(spectrum::make_piecewise_linear(wavelengths, values));
      });
    }
    // Otherwise one value per spectral sample: in RGB mode exactly 3, taken as linear RGB.
    if (tokens.size() != 3)
      doc_.fail(node, "'" + text +
                          "' is not a valid <spectrum> value (1 value, 3 values or "
                          "wavelength:value pairs)");
    if (doc_.mitsuba3())
      doc_.warn(node,
                "a <spectrum> of 3 values is not Mitsuba 3's (which takes one value or "
                "wavelength:value pairs, and refuses this file); read as Mitsuba 0.6's RGB");
  }
  Rgb c;
  if ((kind == "rgb" || kind == "srgb") && tokens.size() == 1 && tokens[0].size() == 7 &&
      tokens[0][0] == '#') {
    // #rrggbb, each byte / 255; like Mitsuba, gamma-decoded only in an <srgb>.
    for (int i = 0; i < 3; ++i) {
      const std::string hex = tokens[0].substr(1 + 2 * i, 2);
      if (!std::isxdigit(static_cast<unsigned char>(hex[0])) ||
          !std::isxdigit(static_cast<unsigned char>(hex[1])))
        doc_.fail(node, "'" + text + "' is not a #rrggbb colour");
      c[i] = float(std::strtol(hex.c_str(), nullptr, 16)) / 255.0f;
    }
  } else {
    std::vector<float> v;
    for (const std::string& token : tokens) v.push_back(doc_.to_float(node, token));
    if (v.size() == 1)
      c = Rgb(v[0]);
    else if (v.size() == 3 && kind != "float")  // RGB mode takes 3 values as they are
      c = Rgb(v[0], v[1], v[2]);
    else
      doc_.fail(node, "'" + text + "' is not a valid <" + kind + "> value");
  }
  if (kind == "srgb") c = Rgb(srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z));
  // Mitsuba 3's RGB variants give a uniform spectrum on an emitter the RGB of an equal-energy
  // white (its XYZ of 1, 1, 1 in sRGB primaries: a purple-ish 1.20, 0.95, 0.91), so that
  // they match its spectral variants; 0.6 and Mitsuba 3 elsewhere give the value itself.
  if (doc_.mitsuba3() && kind == "spectrum" && tokens.size() == 1 &&
      std::string(owner_.name()) == "emitter") {
    const DVec3 white = spectrum::xyz_to_linear_rgb(DVec3(1.0));
    c = Rgb(float(c.x * white.x), float(c.y * white.y), float(c.z * white.z));
  }
  return c;
}

Vec3 Properties::get_point(const std::string& name, const Vec3& fallback) {
  const pugi::xml_node node = take(name, {"point", "vector"});
  if (!node) return fallback;
  if (doc_.has_attribute(node, "value")) {
    const std::vector<float> v = doc_.to_floats(node, doc_.attribute(node, "value"));
    if (v.size() != 3) doc_.fail(node, "'" + name + "' needs 3 numbers");
    return Vec3(v[0], v[1], v[2]);
  }
  Vec3 p(0.0f);
  const char* axes[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (doc_.has_attribute(node, axes[i]))
      p[i] = doc_.to_float(node, doc_.attribute(node, axes[i]));
  return p;
}

Mat4 Properties::get_transform(const std::string& name) {
  const pugi::xml_node node = take(name, {"transform"});
  Mat4 m(1.0f);
  if (!node) return m;
  auto vec3_of = [&](pugi::xml_node op, const char* attribute) {
    const std::vector<float> v = doc_.to_floats(op, doc_.attribute(op, attribute));
    if (v.size() != 3) doc_.fail(op, std::string("'") + attribute + "' needs 3 numbers");
    return Vec3(v[0], v[1], v[2]);
  };
  auto axis_attributes = [&](pugi::xml_node op, float fallback) {
    Vec3 v(fallback);
    const char* axes[] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i)
      if (doc_.has_attribute(op, axes[i])) v[i] = doc_.to_float(op, doc_.attribute(op, axes[i]));
    return v;
  };
  for (pugi::xml_node op : node.children()) {
    if (op.type() != pugi::node_element) continue;
    const std::string kind = op.name();
    Mat4 step(1.0f);
    if (kind == "translate") {
      step =
          glm::translate(Mat4(1.0f), doc_.has_attribute(op, "value") ? vec3_of(op, "value")
                                                                     : axis_attributes(op, 0.0f));
    } else if (kind == "scale") {
      // Mitsuba refuses a <scale> with both forms or neither, rather than guessing.
      const bool has_axes =
          doc_.has_attribute(op, "x") || doc_.has_attribute(op, "y") || doc_.has_attribute(op, "z");
      if (has_axes == doc_.has_attribute(op, "value"))
        doc_.fail(op, has_axes ? "<scale> takes either 'value' or 'x'/'y'/'z', not both"
                               : "<scale> needs 'value' or 'x'/'y'/'z'");
      Vec3 s = axis_attributes(op, 1.0f);
      if (doc_.has_attribute(op, "value")) {
        const std::vector<float> v = doc_.to_floats(op, doc_.attribute(op, "value"));
        if (v.size() == 1)
          s = Vec3(v[0]);
        else if (v.size() == 3)
          s = Vec3(v[0], v[1], v[2]);
        else
          doc_.fail(op, "<scale value=...> needs 1 or 3 numbers");
      }
      step = glm::scale(Mat4(1.0f), s);
    } else if (kind == "rotate") {
      const Vec3 axis =
          doc_.has_attribute(op, "axis") ? vec3_of(op, "axis") : axis_attributes(op, 0.0f);
      if (!doc_.has_attribute(op, "angle")) doc_.fail(op, "<rotate> needs an 'angle' (degrees)");
      if (axis == Vec3(0.0f)) doc_.fail(op, "<rotate> needs a non-zero axis ('x', 'y', 'z')");
      step = loader::rotation_matrix(axis, doc_.to_float(op, doc_.attribute(op, "angle")));
    } else if (kind == "matrix") {
      const std::vector<float> v = doc_.to_floats(op, doc_.attribute(op, "value"));
      if (v.size() != 16 && v.size() != 9) doc_.fail(op, "<matrix> needs 16 (or 9) numbers");
      const int n = v.size() == 16 ? 4 : 3;
      for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) step[col][row] = v[size_t(row * n + col)];
    } else if (kind == "lookat" || kind == "lookAt") {  // Mitsuba accepts both spellings
      for (const char* required : {"origin", "target"})
        if (!doc_.has_attribute(op, required))
          doc_.fail(op, "<" + kind + "> needs '" + required + "'");
      const Vec3 origin = vec3_of(op, "origin"), target = vec3_of(op, "target");
      if (origin == target) doc_.fail(op, "<" + kind + ">: 'origin' and 'target' coincide");
      if (kind == "lookAt" && doc_.mitsuba3())
        doc_.warn(op,
                  "<lookAt> is not a Mitsuba 3 element (it spells it <lookat> and refuses "
                  "this file); read as <lookat>");
      Vec3 up(0.0f);
      if (doc_.has_attribute(op, "up") && !doc_.attribute(op, "up").empty()) up = vec3_of(op, "up");
      if (up == Vec3(0.0f)) up = mitsuba_default_up(origin, target);
      if (!(glm::length(glm::cross(up, target - origin)) > 0.0f))
        doc_.fail(op, "<" + kind + ">: 'up' is parallel to the viewing direction");
      step = look_at_matrix(origin, target, up);
    } else {
      doc_.warn(op, "unsupported transform element <" + kind + "> ignored");
      continue;
    }
    if (!is_finite_matrix(step)) doc_.fail(op, "transform contains NaN or infinite values");
    m = step * m;
    // Finite steps can still overflow together (two scales by 1e30).
    if (!is_finite_matrix(m)) doc_.fail(op, "transform overflows to NaN or infinite values");
  }
  return m;
}

std::vector<std::string> Properties::names_of_kind(const std::string& kind) const {
  std::vector<std::string> names;
  for (const auto& [name, node] : values_)
    if (kind == node.name()) names.push_back(name);
  return names;
}

void Properties::ignore(std::initializer_list<const char*> names) {
  for (const char* name : names) used_.insert(name);
}

void Properties::note_sampling_only(std::initializer_list<const char*> names,
                                    const std::string& what) {
  std::string listed;
  int count = 0;
  for (const char* name : names) {
    if (!has(name) || used(name)) continue;
    // Read as Mitsuba reads it, so that a malformed value is refused as it is there.
    const std::string kind = kind_of(name);
    if (kind == "boolean")
      get_boolean(name, false);
    else if (kind == "integer" || kind == "float")
      get_float(name, 0.0f);
    else
      take(name, {"string"});
    listed += (listed.empty() ? "'" : ", '") + spelled(name) + "'";
    ++count;
  }
  if (count == 0) return;
  doc_.warn(owner_,
            (count == 1 ? "parameter " : "parameters ") + listed + " of " + doc_.describe(owner_) +
                (count == 1 ? " steers only " : " steer only ") + what +
                ", not the image; emlt samples its own way",
            Document::Warning::Note);
}

void Properties::warn_unused() const {
  for (const auto& [name, node] : values_) {
    if (used_.count(name)) continue;
    const std::string where = "parameter '" + spelled(name) + "' of " + doc_.describe(owner_) +
                              " (line " + std::to_string(doc_.line(owner_)) + ")";
    if (name.rfind("mitsuba3:", 0) == 0)  // see values_
      doc_.warn(node, where + " is not one Mitsuba 3 reads; ignored, as Mitsuba 3 does");
    else
      doc_.warn(node, where + " is not supported; ignored");
  }
}

}  // namespace emlt::mitsuba
