// Mitsuba 0.6's delta emitters: `point`, `spot`, `directional` and `collimated`
// (scene/point_light.h, scene/directional_light.h, scene/collimated_light.h), read with Mitsuba's parameters and defaults. In Mitsuba's
// RGB build the D65 default of `intensity`, `irradiance` and `power` is (1, 1, 1).
#include <cmath>

#include "src/scene/loaders/mitsuba_parser.h"
#include "src/scene/parameter_ranges.h"

namespace emlt::mitsuba {

namespace {

constexpr float kDegrees = 3.14159265358979323846f / 180.0f;

// Mitsuba's `position` (a translation) or `toWorld`, never both.
Mat4 light_placement(const Document& doc, pugi::xml_node node, Properties& props) {
  if (props.has("position")) {
    if (props.has("toWorld")) doc.fail(node, "'position' and 'toWorld' cannot be given together");
    Mat4 m(1.0f);
    m[3] = Vec4(props.get_point("position", Vec3(0.0f)), 1.0f);
    return m;
  }
  return props.get_transform("toWorld");
}

// The transform's rotation as unit columns (a scale would change nothing Mitsuba renders
// from a light with no extent, except a spot's falloff, which it reads from a unit axis).
Mat3 unit_axes(const Document& doc, pugi::xml_node node, const Mat4& m) {
  Mat3 axes(m);
  for (int i = 0; i < 3; ++i) {
    const float length = glm::length(axes[i]);
    if (!(length > 0.0f) || !std::isfinite(length))
      doc.fail(node, "the light's 'toWorld' is singular");
    axes[i] /= length;
  }
  return axes;
}

void read_point(const Document& doc, pugi::xml_node node, Properties& props, bool spot,
                NamedObjects& named, SceneDescription& desc) {
  PointLightDesc light;
  const Mat4 m = light_placement(doc, node, props);
  light.position = Vec3(m[3]);
  light.orientation = unit_axes(doc, node, m);
  light.intensity = props.get_color("intensity", Rgb(1.0f));
  if (spot) {
    light.spot = true;
    const float cutoff = props.get_float("cutoffAngle", 20.0f, loader::kFovRange);
    const float beam = props.get_float("beamWidth", cutoff * 0.75f, loader::kFovRange);
    if (beam > cutoff) doc.fail(node, "'beamWidth' must not exceed 'cutoffAngle'");
    // Mitsuba's cutoff is the half-angle of the cone: past 90 degrees the projected
    // texture's coordinates are undefined, as in Mitsuba.
    light.cutoff = cutoff * kDegrees;
    light.beam_width = beam * kDegrees;
    if (props.has("texture")) {
      TexturePtr texture = props.get_texture("texture", Rgb(1.0f), named);
      // Mitsuba 0.6 reads a spot's texture only when it varies: a constant one leaves
      // the beam white.
      if (texture && texture->constant())
        doc.warn(node,
                 "a constant 'texture' leaves a Mitsuba 0.6 spot white; ignored as Mitsuba does",
                 Document::Warning::Note);
      else
        light.texture = std::move(texture);
    }
  }
  desc.point_lights.push_back(std::move(light));
}

void read_directional(const Document& doc, pugi::xml_node node, Properties& props,
                      SceneDescription& desc) {
  DirectionalLightDesc light;
  if (props.has("direction")) {
    if (props.has("toWorld")) doc.fail(node, "'direction' and 'toWorld' cannot be given together");
    light.direction = props.get_point("direction", Vec3(0.0f, 0.0f, 1.0f));
  } else {
    light.direction = Mat3(props.get_transform("toWorld")) * Vec3(0.0f, 0.0f, 1.0f);
  }
  if (!(glm::length(light.direction) > 0.0f) || !is_finite(light.direction))
    doc.fail(node, "the directional light's direction has no length");
  light.direction = glm::normalize(light.direction);
  light.irradiance = props.get_color("irradiance", Rgb(1.0f));
  desc.directional_lights.push_back(light);
}

// Mitsuba's beam leaves toWorld's origin along its z axis; it refuses a toWorld that scales.
void read_collimated(const Document& doc, pugi::xml_node node, Properties& props,
                     SceneDescription& desc) {
  const Mat4 m = props.get_transform("toWorld");
  for (int i = 0; i < 3; ++i)
    if (std::abs(glm::length(Vec3(m[i])) - 1.0f) > 1e-4f)
      doc.fail(node, "a collimated beam's 'toWorld' must not scale (Mitsuba refuses it too)");
  CollimatedLightDesc beam;
  beam.origin = Vec3(m[3]);
  beam.direction = glm::normalize(Mat3(m) * Vec3(0.0f, 0.0f, 1.0f));
  beam.power = props.get_color("power", Rgb(1.0f));
  desc.collimated_lights.push_back(beam);
}

}  // namespace

bool read_delta_light(const Document& doc, pugi::xml_node node, NamedObjects& named,
                      SceneDescription& desc) {
  const std::string type = doc.attribute(node, "type");
  if (type != "point" && type != "spot" && type != "directional" && type != "collimated")
    return false;
  Properties props(doc, node);
  props.note_sampling_only({"samplingWeight"}, "how often Mitsuba samples this light");
  if (type == "directional")
    read_directional(doc, node, props, desc);
  else if (type == "collimated")
    read_collimated(doc, node, props, desc);
  else
    read_point(doc, node, props, type == "spot", named, desc);
  for (pugi::xml_node child : props.objects())
    doc.warn(child, "unsupported element " + doc.describe(child) + " inside <emitter> ignored");
  props.warn_unused();
  return true;
}

}  // namespace emlt::mitsuba
