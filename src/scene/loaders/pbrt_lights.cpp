// pbrt-v4's lights: AreaLightSource "diffuse" (one-sided, as pbrt's default), and
// LightSource "point", "spot", "distant" and "infinite" (a constant L, or an image resampled
// by pbrt_infinite_map.cpp). "goniometric" and "projection" are refused loudly: warned,
// counted in the verdict and left out.
#include <fmt/format.h>

#include <cmath>

#include "emlt/scene/shape_builders.h"
#include "src/scene/loaders/pbrt_reader.h"

namespace emlt::pbrt {

namespace {

// A unit frame whose third column is `z`.
Mat3 frame_from_z(const Vec3& z) {
  const Vec3 helper = std::abs(z.x) < 0.9f ? Vec3(1.0f, 0.0f, 0.0f) : Vec3(0.0f, 1.0f, 0.0f);
  const Vec3 x = glm::normalize(glm::cross(helper, z));
  return Mat3(x, glm::cross(z, x), z);
}

}  // namespace

void Reader::area_light(const Where& at, const std::string& type, const Params& params) {
  if (type != "diffuse") fail(at, "unknown area light type '" + type + "' (diffuse)");
  const Rgb radiance = color(params, "L", Rgb(1.0f)) * params.get_float("scale", 1.0f);
  if (!is_finite(radiance) || radiance.x < 0.0f || radiance.y < 0.0f || radiance.z < 0.0f)
    fail(at, "AreaLightSource: L times scale must be finite and not negative");
  if (params.get_bool("twosided", false))
    warn(at,
         "AreaLightSource 'twosided' is not supported: the shapes emit on their front side "
         "only (half of pbrt's light)");
  for (const char* name : {"filename", "power"})
    if (const Param* p = params.get(name))
      warn({p->file, p->line}, "AreaLightSource " + p->quoted() + " is not supported; ignored");
  report_unused(params, "AreaLightSource \"diffuse\"");
  state_.area_light = radiance;
}

void Reader::light(const Where& at, const std::string& type, const Params& params) {
  const std::string what = "LightSource \"" + type + "\"";
  const Mat4& ctm = state_.ctm;
  if (!is_finite_matrix(ctm)) fail(at, what + ": the transformation has NaN or infinity");
  const float scale = params.get_float("scale", 1.0f);
  for (const char* name : {"power", "illuminance"})
    if (const Param* p = params.get(name))
      warn({p->file, p->line}, what + " " + p->quoted() +
                                   " (normalising the light to a power) is not supported; ignored");
  auto check = [&](const Rgb& c) {
    if (!is_finite(c) || c.x < 0.0f || c.y < 0.0f || c.z < 0.0f)
      fail(at, what + ": the emitted light times scale must be finite and not negative");
    return c;
  };
  if (type == "point" || type == "spot") {
    PointLightDesc light;
    const Vec3 from = params.get_point3("from", Vec3(0.0f));
    light.position = Vec3(ctm * Vec4(from, 1.0f));
    light.intensity = check(color(params, "I", Rgb(1.0f)) * scale);
    if (type == "spot") {
      const Vec3 to = params.get_point3("to", Vec3(0.0f, 0.0f, 1.0f));
      const Vec3 axis = Vec3(ctm * Vec4(to - from, 0.0f));
      if (!(glm::length(axis) > 0.0f)) fail(at, what + ": 'from' and 'to' must differ");
      light.spot = true;
      light.orientation = frame_from_z(glm::normalize(axis));
      // pbrt-v4's names and defaults: the cone's half-angle, and the angle over which the
      // intensity falls off inside it, in degrees.
      const float cone = params.get_float("coneangle", 30.0f),
                  delta = params.get_float("conedeltaangle", 5.0f);
      if (!(cone > 0.0f && cone <= 180.0f) || !(delta >= 0.0f && delta <= cone))
        fail(at, what + ": coneangle must be in (0, 180] and conedeltaangle in [0, coneangle]");
      light.cutoff = glm::radians(cone);
      light.beam_width = glm::radians(cone - delta);
      if (delta > 0.0f)
        warn(at,
             what +
                 ": the falloff over conedeltaangle is linear in angle (Mitsuba's spot); "
                 "pbrt's is a smoothstep in the cosine",
             Divergence::Kind::Approximated);
    }
    report_unused(params, what);
    desc_.point_lights.push_back(light);
  } else if (type == "distant") {
    DirectionalLightDesc light;
    const Vec3 from = params.get_point3("from", Vec3(0.0f)),
               to = params.get_point3("to", Vec3(0.0f, 0.0f, 1.0f));
    // The light arrives from `from`'s side: it travels along to - from.
    const Vec3 travel = Vec3(ctm * Vec4(to - from, 0.0f));
    if (!(glm::length(travel) > 0.0f)) fail(at, what + ": 'from' and 'to' must differ");
    light.direction = glm::normalize(travel);
    light.irradiance = check(color(params, "L", Rgb(1.0f)) * scale);
    report_unused(params, what);
    desc_.directional_lights.push_back(light);
  } else if (type == "infinite") {
    params.ignore("portal");  // where pbrt samples the light, not what it emits
    if (desc_.environment.kind != EnvironmentDesc::Kind::None) {
      for (const Param* p : params.unused()) p->used = true;
      warn(at, what + ": only one infinite light is supported; this one is left out");
      return;
    }
    if (params.has("filename")) {
      if (params.has("L")) fail(at, what + ": both 'L' and 'filename' given");
      if (!(scale >= 0.0f)) fail(at, what + ": scale must not be negative");
      infinite_map(at, params.get_string("filename", ""), scale);
      report_unused(params, what);
      return;
    }
    desc_.environment.kind = EnvironmentDesc::Kind::Constant;
    desc_.environment.radiance = check(color(params, "L", Rgb(1.0f)) * scale);
    report_unused(params, what);
  } else if (type == "goniometric" || type == "projection") {
    for (const Param* p : params.unused()) p->used = true;
    warn(at, what + " is not supported; the light is left out");
  } else {
    fail(at, "unknown light type '" + type + "'");
  }
}

}  // namespace emlt::pbrt
