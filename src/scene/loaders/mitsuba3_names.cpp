#include "src/scene/loaders/mitsuba3_names.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <initializer_list>
#include <utility>

#include "src/scene/loaders/mitsuba_parser.h"

namespace emlt::mitsuba {

namespace {

bool one_of(std::string_view value, std::initializer_list<std::string_view> list) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

// Mitsuba 3's snake_case parameters whose meaning is the 0.6 parameter's, by the 0.6 name
// the readers ask for. A name Mitsuba 3 reads with a changed meaning is still listed when
// the reader applies the change itself (max_depth's, focal_length's); what it reads under
// a name of its own (to_uv, raw) maps to that name.
constexpr std::pair<std::string_view, std::string_view> kRenamed[] = {
    // scene objects and transforms
    {"to_world", "toWorld"},
    // the Mitchell-Netravali filter keeps its capitals in Mitsuba 3
    {"B", "B"},
    {"C", "C"},
    // integrators (MonteCarloIntegrator and Integrator, direct)
    {"max_depth", "maxDepth"},
    {"rr_depth", "rrDepth"},
    {"hide_emitters", "hideEmitters"},
    {"emitter_samples", "emitterSamples"},
    {"bsdf_samples", "bsdfSamples"},
    {"shading_samples", "shadingSamples"},
    {"samples_per_pass", "samples_per_pass"},  // ptracer: how the work is cut, sampling only
    // samplers
    {"sample_count", "sampleCount"},
    // sensors
    {"fov_axis", "fovAxis"},
    {"near_clip", "nearClip"},
    {"far_clip", "farClip"},
    {"focal_length", "focalLength"},
    {"focus_distance", "focusDistance"},
    {"aperture_radius", "apertureRadius"},
    {"shutter_open", "shutterOpen"},
    {"shutter_close", "shutterClose"},
    // films: sample_border is 0.6's highQualityEdges (samples taken just outside the image)
    {"pixel_format", "pixelFormat"},
    {"component_format", "componentFormat"},
    {"file_format", "fileFormat"},
    {"sample_border", "highQualityEdges"},
    {"crop_offset_x", "cropOffsetX"},
    {"crop_offset_y", "cropOffsetY"},
    {"crop_width", "cropWidth"},
    {"crop_height", "cropHeight"},
    // shapes
    {"face_normals", "faceNormals"},
    {"flip_normals", "flipNormals"},
    {"flip_tex_coords", "flipTexCoords"},
    {"shape_index", "shapeIndex"},
    // BSDFs
    {"int_ior", "intIOR"},
    {"ext_ior", "extIOR"},
    {"specular_reflectance", "specularReflectance"},
    {"specular_transmittance", "specularTransmittance"},
    {"diffuse_reflectance", "diffuseReflectance"},
    {"alpha_u", "alphaU"},
    {"alpha_v", "alphaV"},
    {"sample_visible", "sampleVisible"},
    {"use_shadowing_function", "use_shadowing_function"},  // bumpmap, Mitsuba 3 only
    {"flip_invalid_normals", "flip_invalid_normals"},      // bumpmap, Mitsuba 3 only
    {"base_color", "base_color"},                          // principled (not supported)
    // emitters
    {"sampling_weight", "samplingWeight"},
    {"cutoff_angle", "cutoffAngle"},
    {"beam_width", "beamWidth"},
    {"mis_compensation", "mis_compensation"},  // envmap: sampling only
    // textures
    {"wrap_mode", "wrapMode"},
    {"filter_type", "filterType"},
    {"to_uv", "to_uv"},
};

// One-word parameters of 0.6 that Mitsuba 3 no longer reads on that element: a Mitsuba 3
// file giving one gets no 0.6 meaning from emlt either.
bool dropped_in_mitsuba3(std::string_view element, std::string_view type, std::string_view name) {
  if (element == "texture")
    return one_of(name, {"gamma", "channel", "uvscale", "uscale", "vscale", "uoffset", "voffset",
                         "cache"}) ||
           (type == "bitmap" && name == "srgb");
  if (element == "emitter") return one_of(name, {"cache", "gamma"});
  if (element == "shape" && type == "ply") return name == "srgb";
  return false;
}

}  // namespace

bool is_mitsuba3_version(std::string_view version) {
  const size_t dot = version.find('.');
  const std::string major(version.substr(0, dot));
  if (major.empty() || !std::all_of(major.begin(), major.end(), [](char c) {
        return std::isdigit(static_cast<unsigned char>(c));
      }))
    return false;
  const long value = std::strtol(major.c_str(), nullptr, 10);
  return value == 2 || value == 3;
}

std::string mitsuba3_key(std::string_view element, std::string_view type, std::string_view name) {
  for (const auto& [snake, key] : kRenamed)
    if (name == snake) return std::string(key);
  // Mitsuba 3 spells every parameter in lower case; a name with a capital letter is a 0.6
  // one, which Mitsuba 3 leaves unread.
  const bool lower_word = !name.empty() && std::none_of(name.begin(), name.end(), [](char c) {
    return std::isupper(static_cast<unsigned char>(c)) || c == '_';
  });
  if (!lower_word || dropped_in_mitsuba3(element, type, name)) return "";
  return std::string(name);  // a one-word name means the same in both (reflectance, fov ...)
}

bool mitsuba06_only_plugin(std::string_view element, std::string_view type) {
  // Mitsuba 3 dropped these 0.6 plugins (its bsdfs are blendbsdf, bumpmap, conductor,
  // dielectric, diffuse, mask, normalmap, plastic, principled, the rough ones, thindielectric,
  // twosided and a few polarised or measured ones; its textures bitmap and checkerboard; its
  // integrators path, direct, ptracer, volpath and AOV-like ones; its films hdrfilm and
  // specfilm; its samplers independent, stratified, multijitter, orthogonal and ldsampler).
  // Listed are those the 0.6 readers render without an item of their own: the 0.6 plugins
  // emlt lacks too (pssmlt ...) are reported by the readers already.
  if (element == "bsdf")
    return one_of(type, {"phong", "ward", "roughdiffuse", "difftrans", "mixturebsdf", "coating",
                         "roughcoating"});
  if (element == "texture") return type == "scale" || type == "gridtexture";
  if (element == "integrator") return one_of(type, {"bdpt", "mlt"});
  if (element == "film") return one_of(type, {"ldrfilm", "mfilm", "tiledhdrfilm"});
  if (element == "sampler") return one_of(type, {"halton", "hammersley", "sobol"});
  if (element == "emitter") return one_of(type, {"sky", "sun"});
  return false;
}

// The parser layer's checks that only a Mitsuba 3 file needs (mitsuba_parser.h).

void Document::check_mitsuba3_plugins(pugi::xml_node node) const {
  for (pugi::xml_node child : node.children()) {
    if (child.type() != pugi::node_element) continue;
    // The type as written: a `$name` in it is resolved only once the defaults are known,
    // and a plugin named through one is checked by its reader alone.
    if (mitsuba06_only_plugin(child.name(), child.attribute("type").as_string()))
      warn(child, "Mitsuba 3 has no " + describe(child) +
                      " plugin (it refuses this file); read as Mitsuba 0.6's");
    // Mitsuba 3.6 brought a sunsky of its own: another sky model, with other parameters.
    if (std::string_view(child.name()) == "emitter" &&
        std::string_view(child.attribute("type").as_string()) == "sunsky")
      warn(child, "Mitsuba 3's <emitter type=\"sunsky\"> is another sky model than 0.6's, "
                  "with other parameters; read as Mitsuba 0.6's");
    check_mitsuba3_plugins(child);
  }
}

void Properties::mitsuba3_colour_forms(pugi::xml_node node) const {
  const std::string kind = node.name();
  const std::string refused = " (Mitsuba 3 refuses this file)";
  if (kind == "srgb" || kind == "blackbody")
    doc_.warn(node, "<" + kind + "> is not a Mitsuba 3 element" + refused +
                        "; read as Mitsuba 0.6's " +
                        (kind == "srgb" ? "sRGB-encoded colour" : "black body"));
  if (doc_.has_attribute(node, "intent"))
    doc_.warn(node,
              "'intent' is not a Mitsuba 3 attribute" + refused + "; it changes nothing in RGB");
  const std::string value = doc_.attribute(node, "value");
  if (kind == "rgb" && value.find('#') != std::string::npos)
    doc_.warn(node, "a #rrggbb <rgb> is not Mitsuba 3's" + refused +
                        "; read as Mitsuba 0.6's (each byte / 255, linear)");
  // A measured spectrum: Mitsuba 3's RGB variants weight a reflectance by the D65
  // illuminant, clip it to [0, 1] and sum 1000 samples of its own CIE table; emlt converts
  // it as 0.6 does, which differs by up to a few per cent.
  if (kind == "spectrum" &&
      (doc_.has_attribute(node, "filename") || value.find(':') != std::string::npos))
    doc_.warn(node,
              "measured <spectrum> converted to RGB as Mitsuba 0.6 does; Mitsuba 3 weights a "
              "reflectance spectrum by D65 and clips it to [0, 1] (a few per cent apart)",
              Document::Warning::Approximated);
}

}  // namespace emlt::mitsuba
