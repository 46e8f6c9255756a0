// Mitsuba 0.6's `sky`, `sun` and `sunsky` emitters: every parameter their plugins read,
// checked as Mitsuba checks it, turned into the lat-long image Mitsuba rasterises and hands
// to a nested `envmap` (src/emitters/sky.cpp, sun.cpp, sunsky.cpp there).
//
// What Mitsuba does that this repeats:
// - The sun's position comes from `sunDirection` (a world-space vector, taken into the
//   emitter's frame by the inverse of toWorld) or else from date, time and place; giving
//   `sunDirection` together with latitude, longitude, timezone or day is an error.
// - `sky` refuses turbidity outside [1, 10], stretch outside [1, 2], an albedo channel
//   outside [0, 1] and a sun below the horizon; `sun` checks none of these.
// - `sunsky` is its sky (scaled by skyScale) plus its sun (scaled by sunScale) in one map;
//   both default to `scale`.
// - `sun` and `sunsky` with sunRadiusScale 0 make the sun a directional light instead.
//   emlt cannot render delta lights yet: that sun is refused as an unsupported item
//   (sunsky keeps its sky).
#include "src/scene/loaders/mitsuba_sky.h"

#include <fmt/core.h>

#include <cmath>

#include "emlt/scene/sky.h"

namespace emlt::mitsuba {

namespace {

constexpr loader::RealRange kTurbidityRange{1.0f, false, 10.0f, false,
                                            "a number from 1 to 10 (Mitsuba's sky model)"};
constexpr loader::RealRange kStretchRange{1.0f, false, 2.0f, false, "a number from 1 to 2"};
// Mitsuba's map is resolution x resolution/2; 16384 is as far as emlt's film sides go.
constexpr loader::IntegerRange kResolutionRange{
    2, 16384, "a whole number of pixels from 2 to 16384 (the map is that wide, half as high)"};

double degrees(float radians) {
  return radians * 180.0 / 3.14159265358979323846;
}

// The sun's direction in the emitter's own frame (emlt/scene/sky.h), as Mitsuba's
// computeSunCoordinates reads it.
sky::SkyAngles read_sun_position(const Document& doc, Properties& props, const Mat4& to_world) {
  if (props.has("sunDirection")) {
    for (const char* name : {"latitude", "longitude", "timezone", "day", "time"})
      if (props.has(name))
        doc.fail(props.node_of(name),
                 std::string("'sunDirection' and '") + name +
                     "' both given: the sun's direction or the time and place, not both "
                     "(Mitsuba 0.6 refuses this too)");
    // Mitsuba ignores the rest of the date and time then, without a word.
    for (const char* name : {"year", "month", "hour", "minute", "second"})
      if (props.has(name))
        doc.warn(props.node_of(name),
                 std::string("'") + name + "' is ignored where 'sunDirection' is given (as " +
                     "Mitsuba 0.6 ignores it)",
                 Document::Warning::Note);
    props.ignore({"year", "month", "hour", "minute", "second"});
    const Vec3 world = props.get_point("sunDirection", Vec3(0.0f, 1.0f, 0.0f));
    const Vec3 local = glm::inverse(glm::mat3(to_world)) * world;
    if (!(glm::length(local) > 0.0f) || !std::isfinite(glm::length(local)))
      doc.fail(props.node_of("sunDirection"), "'sunDirection' must be a non-zero vector");
    return sky::angles_of(glm::normalize(local));
  }
  sky::Observation when;
  when.latitude = props.get_float("latitude", when.latitude);
  when.longitude = props.get_float("longitude", when.longitude);
  when.timezone = props.get_float("timezone", when.timezone);
  when.year = props.get_integer("year", when.year);
  when.day = props.get_integer("day", when.day);
  when.month = props.get_integer("month", when.month);
  when.hour = props.get_float("hour", when.hour);
  when.minute = props.get_float("minute", when.minute);
  when.second = props.get_float("second", when.second);
  return sky::sun_angles(when);
}

sky::SkyParameters read_sky_parameters(const Document& doc, Properties& props, float scale) {
  sky::SkyParameters p;
  p.scale = scale;
  p.turbidity = props.get_float("turbidity", p.turbidity, kTurbidityRange);
  p.stretch = props.get_float("stretch", p.stretch, kStretchRange);
  p.albedo = props.get_color("albedo", p.albedo);
  if (glm::any(glm::lessThan(p.albedo, Rgb(0.0f))) ||
      glm::any(glm::greaterThan(p.albedo, Rgb(1.0f))))
    doc.fail(props.node_of("albedo"),
             fmt::format("'albedo' must lie in [0, 1] in every channel (got {}, {}, {} in RGB)",
                         p.albedo.x, p.albedo.y, p.albedo.z));
  p.extend = props.get_boolean("extend", false);
  return p;
}

// The sky's map; Mitsuba refuses a sun below the horizon.
Image sky_map(const Document& doc, pugi::xml_node node, const sky::SkyParameters& p,
              const sky::SkyAngles& sun, int resolution, bool round_trip) {
  if (sun.zenith > 0.5 * 3.14159265358979323846)
    doc.fail(node, fmt::format("the sun is {:.2f} degrees below the horizon; Mitsuba 0.6's "
                               "sky model refuses a sun below the horizon",
                               degrees(sun.zenith) - 90.0));
  return sky::rasterize_sky(sky::SkyModel(p, sun), resolution, round_trip);
}

Rgb checked_sun_radiance(const Document& doc, pugi::xml_node node, const sky::SkyAngles& sun,
                         float turbidity) {
  const Rgb radiance = sky::sun_radiance(sun.zenith, turbidity);
  // Far below the horizon the air-mass formula has no value (Mitsuba renders NaN).
  if (!is_finite(radiance))
    doc.fail(node, fmt::format("the sun, {:.2f} degrees below the horizon, has no radiance "
                               "in the sun model (turbidity {})",
                               degrees(sun.zenith) - 90.0, turbidity));
  return radiance;
}

// Mitsuba's sun with sunRadiusScale 0: parallel light from the sun's (stretched) direction,
// of the irradiance its disk would deliver, the radiance times the disk's solid angle (in
// single precision, as Mitsuba computes it).
DirectionalLightDesc directional_sun(const sky::SkyAngles& shown, const Rgb& radiance,
                                     const Mat4& to_world) {
  const float theta =
      float(sky::kSunApparentDiameterDegrees * 0.5) * (3.14159265358979f / 180.0f);
  const float solid_angle = 2.0f * 3.14159265358979f * (1.0f - std::cos(theta));
  DirectionalLightDesc light;
  light.direction = -glm::normalize(Mat3(to_world) * sky::direction_of(shown));
  light.irradiance = radiance * solid_angle;
  return light;
}

}  // namespace

bool is_sky_emitter(const std::string& type) {
  return type == "sky" || type == "sun" || type == "sunsky";
}

void read_sky_emitter(const Document& doc, pugi::xml_node node, SceneDescription& desc) {
  EnvironmentDesc& env = desc.environment;
  const std::string type = doc.attribute(node, "type");
  // Each of these is an environment emitter in Mitsuba, which loads no scene with two
  // ("The scene may only contain one environment emitter"): a `sun` beside a `sky` is
  // written as one `sunsky`.
  if (env.kind != EnvironmentDesc::Kind::None)
    doc.fail(node,
             "a second environment emitter: Mitsuba 0.6 refuses a scene with more than "
             "one (a sun and a sky together are one <emitter type=\"sunsky\">)");
  Properties props(doc, node);
  props.note_sampling_only({"samplingWeight"}, "how often Mitsuba samples this light");
  const Mat4 to_world = props.get_transform("toWorld");
  const float scale = props.get_float("scale", 1.0f, loader::kNonNegativeRange);
  const int resolution = props.get_integer("resolution", 512, kResolutionRange);
  const sky::SkyAngles sun = read_sun_position(doc, props, to_world);

  Image map;
  bool has_map = true;
  if (type == "sky") {
    map = sky_map(doc, node, read_sky_parameters(doc, props, scale), sun, resolution, false);
  } else {
    const float sun_scale =
        type == "sun" ? scale : props.get_float("sunScale", scale, loader::kNonNegativeRange);
    const float radius_scale = props.get_float("sunRadiusScale", 1.0f, loader::kNonNegativeRange);
    const float turbidity = type == "sun" ? props.get_float("turbidity", 3.0f)
                                          : props.get_float("turbidity", 3.0f, kTurbidityRange);
    const float stretch = type == "sun" ? props.get_float("stretch", 1.0f)
                                        : props.get_float("stretch", 1.0f, kStretchRange);
    if (type == "sunsky") {
      const float sky_scale = props.get_float("skyScale", scale, loader::kNonNegativeRange);
      sky::SkyParameters p = read_sky_parameters(doc, props, sky_scale);
      // sunsky evaluates its sky through each pixel's direction and back.
      map = sky_map(doc, node, p, sun, resolution, true);
    } else {
      map = Image(resolution, resolution / 2);
    }
    // The sun's radiance is that of its true position; `stretch` then lifts its place
    // (the sky squeezes its zenith angles by the same factor).
    const Rgb radiance = checked_sun_radiance(doc, node, sun, turbidity) * sun_scale;
    const sky::SkyAngles shown{sun.zenith * stretch, sun.azimuth};
    if (radius_scale > 0.0f) {
      sky::add_sun(map, shown, radiance, radius_scale);
    } else {
      desc.directional_lights.push_back(directional_sun(shown, radiance, to_world));
      has_map = type == "sunsky";  // a `sun` is then the directional light alone
    }
  }
  if (has_map) {
    env.kind = EnvironmentDesc::Kind::Map;
    env.map = std::move(map);
    env.map_path = doc.path() + ": line " + std::to_string(doc.line(node)) + ": the " + type +
                   " emitter's map";
    env.scale = 1.0f;  // the map carries the emitter's scale, as Mitsuba's does
    env.to_world = to_world;
  }
  for (pugi::xml_node child : props.objects())
    doc.warn(child, "unsupported element " + doc.describe(child) + " inside <emitter> ignored");
  props.warn_unused();
}

}  // namespace emlt::mitsuba
