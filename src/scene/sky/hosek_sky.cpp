// The Hosek-Wilkie sky in its RGB fit, and the `sky` emitter's lat-long map of it
// (emlt/scene/sky.h).
//
// The model: radiance(theta, gamma) = (1 + A exp(B / (cos theta + 0.01))) *
//   (C + D exp(E gamma) + F cos^2 gamma + G chi(H, gamma) + I sqrt(cos theta)) * L,
// theta the view's zenith angle, gamma its angle to the sun, chi the anisotropic term
// (1 + cos^2 gamma) / (1 + H^2 - 2 H cos gamma)^1.5. A..I and the scale L come from the
// dataset, blended for the sun's elevation (a quintic Bezier in (elevation / (pi/2))^(1/3)),
// linearly for the turbidity between its integer neighbours, and linearly for the ground
// albedo between 0 and 1.
//
// Mitsuba evaluates the model in double precision from single-precision angles and keeps
// single-precision results; so does this, so that maps agree to float rounding.
#include <algorithm>
#include <cmath>

#include "emlt/scene/sky.h"

namespace emlt::sky {

namespace {

#include "src/scene/sky/hosek_wilkie_rgb.inc"

constexpr double kPiD = 3.14159265358979323846;
// Mitsuba divides the RGB fit by the sum of its tabulated CIE y-bar (1 nm steps) so that
// a sky's RGB is in the units of its spectral radiance (per nm) rather than integrated.
constexpr double kRgbNormalisation = 106.856980;
// Mitsuba's single-precision `Epsilon`: how far above the horizon `extend` looks.
constexpr float kHorizonEpsilon = 1e-4f;

// The quintic Bezier blend of six control points at s = (elevation / (pi/2))^(1/3);
// `stride` separates consecutive control points in the table.
double bezier(const double* points, int stride, double s) {
  const double t = 1.0 - s;
  return std::pow(t, 5.0) * points[0] + 5.0 * std::pow(t, 4.0) * s * points[stride] +
         10.0 * std::pow(t, 3.0) * std::pow(s, 2.0) * points[2 * stride] +
         10.0 * std::pow(t, 2.0) * std::pow(s, 3.0) * points[3 * stride] +
         5.0 * t * std::pow(s, 4.0) * points[4 * stride] + std::pow(s, 5.0) * points[5 * stride];
}

// Coefficients (count 9) or radiance scale (count 1) of one channel for the given sky: the
// blend over the (albedo, turbidity) corners around it.
void cook(const double* table, int count, double turbidity, double albedo, double elevation,
          double* out) {
  const int low = int(turbidity);  // 1..10 (checked by the loader)
  const double rem = turbidity - double(low);
  const double s = std::pow(elevation / (kPiD / 2.0), 1.0 / 3.0);
  const int block = 6 * count;  // one (albedo, turbidity) entry
  struct Corner {
    int albedo, turbidity;
    double weight;
  };
  const Corner corners[4] = {{0, low, (1.0 - albedo) * (1.0 - rem)},
                             {1, low, albedo * (1.0 - rem)},
                             {0, low + 1, (1.0 - albedo) * rem},
                             {1, low + 1, albedo * rem}};
  for (int i = 0; i < count; ++i) out[i] = 0.0;
  // At turbidity 10 the upper neighbour does not exist (and its weight is 0).
  const int used = low == 10 ? 2 : 4;
  for (int k = 0; k < used; ++k) {
    const double* entry = table + block * (10 * corners[k].albedo + (corners[k].turbidity - 1));
    for (int i = 0; i < count; ++i) out[i] += corners[k].weight * bezier(entry + i, count, s);
  }
}

double evaluate(const double* c, double theta, double gamma) {
  const double cos_gamma = std::cos(gamma), cos_theta = std::cos(theta);
  const double glow = std::exp(c[4] * gamma);
  const double rayleigh = cos_gamma * cos_gamma;
  const double mie =
      (1.0 + cos_gamma * cos_gamma) / std::pow(1.0 + c[8] * c[8] - 2.0 * c[8] * cos_gamma, 1.5);
  const double zenith = std::sqrt(cos_theta);
  return (1.0 + c[0] * std::exp(c[1] / (cos_theta + 0.01))) *
         (c[2] + c[3] * glow + c[5] * rayleigh + c[6] * mie + c[7] * zenith);
}

float smooth_step(float x) {
  const float v = std::clamp(x, 0.0f, 1.0f);
  return v * v * (3.0f - 2.0f * v);
}

}  // namespace

SkyModel::SkyModel(const SkyParameters& parameters, const SkyAngles& sun)
    : parameters_(parameters), sun_(sun) {
  const float elevation = float(0.5f * kPiD - sun.zenith);
  for (int c = 0; c < 3; ++c) {
    // Each channel is its own model with its own ground albedo.
    cook(kHosekRgbCoefficients[c], 9, parameters.turbidity, parameters.albedo[c], elevation,
         config_[c]);
    cook(kHosekRgbRadiance[c], 1, parameters.turbidity, parameters.albedo[c], elevation,
         &level_[c]);
  }
}

Rgb SkyModel::radiance(const SkyAngles& view) const {
  float theta = view.zenith / parameters_.stretch;
  if (std::cos(theta) <= 0.0f) {
    if (!parameters_.extend) return Rgb(0.0f);
    theta = float(0.5f * kPiD - kHorizonEpsilon);
  }
  const float cos_gamma =
      std::cos(theta) * std::cos(sun_.zenith) +
      std::sin(theta) * std::sin(sun_.zenith) * std::cos(view.azimuth - sun_.azimuth);
  const float gamma = std::acos(std::clamp(cos_gamma, -1.0f, 1.0f));
  Rgb result;
  for (int c = 0; c < 3; ++c)
    result[c] = float(evaluate(config_[c], theta, gamma) * level_[c] / kRgbNormalisation);
  result = glm::max(result, Rgb(0.0f));
  // `extend` fades the continued horizon out towards the nadir.
  if (parameters_.extend) result *= smooth_step(2.0f - 2.0f * view.zenith * kInvPi);
  return result * parameters_.scale;
}

Image rasterize_sky(const SkyModel& model, int resolution, bool round_trip) {
  Image map(resolution, resolution / 2);
  const float step_phi = float((2 * kPiD) / map.width), step_theta = float(kPiD / map.height);
  for (int y = 0; y < map.height; ++y) {
    const float theta = (y + 0.5f) * step_theta;
    for (int x = 0; x < map.width; ++x) {
      SkyAngles view{theta, (x + 0.5f) * step_phi};
      if (round_trip) view = angles_of(direction_of(view));
      map.at(x, y) = model.radiance(view);
    }
  }
  return map;
}

}  // namespace emlt::sky
