#pragma once
// Daylight as Mitsuba 0.6 means it: the `sky`, `sun` and `sunsky` emitters are not lights of
// their own there but latitude-longitude images their plugins rasterise once and hand to
// a nested `envmap`. This builds the same images (same size, pixel mapping, conventions
// and spectral-to-RGB path as Mitsuba's default RGB, single-precision build), so that
// emlt's environment map renders them as Mitsuba does.
//
// The models:
// - sky: Hosek & Wilkie, "An Analytic Model for Full Spectral Sky-Dome Radiance" (SIGGRAPH
//   2012), its RGB fit, one channel at a time with that channel's ground albedo.
// - sun: the spectral solar radiance of Preetham, Shirley & Smits, "A Practical Analytic
//   Model for Daylight" (SIGGRAPH 1999): the extraterrestrial spectrum attenuated by
//   Rayleigh, aerosol, ozone, mixed-gas and water-vapour transmittance, turned into RGB
//   through the CIE 1931 observer (emlt/scene/spectrum.h).
// - sun position: the PSA algorithm of Blanco-Muriel et al., "Computing the Solar Vector"
//   (Solar Energy 70(5), 2001), from date, local time and place.
//
// Frame (the emitter's local space, before its toWorld): +Y is up, +X east, +Z north. A
// direction's zenith angle is measured from +Y and its azimuth is atan2(x, -z) in
// [0, 2 pi). Pixel (x, y) of a W x H map holds the direction at azimuth (x + 1/2) 2 pi / W
// and zenith angle (y + 1/2) pi / H: row 0 is the zenith, the map's left edge looks
// towards -Z. This is the mapping of emlt's (and Mitsuba's) `envmap`.
#include "emlt/core/math.h"
#include "emlt/image/image.h"

namespace emlt::sky {

// A direction of the local frame in spherical coordinates (radians).
struct SkyAngles {
  float zenith = 0.0f;   // from +Y (Mitsuba calls it "elevation")
  float azimuth = 0.0f;  // atan2(x, -z), in [0, 2 pi)
};

Vec3 direction_of(const SkyAngles& angles);
// `direction` of unit length (a longer one's y would be clamped to [-1, 1]).
SkyAngles angles_of(const Vec3& direction);

// An observation: local date and time at a place (Mitsuba's defaults: 3 PM on 10 July
// 2010 in Tokyo). No daylight saving time: the time is the timezone's standard time.
struct Observation {
  int year = 2010, month = 7, day = 10;
  float hour = 15.0f, minute = 0.0f, second = 0.0f;
  float latitude = 35.6894f;    // degrees, north positive
  float longitude = 139.6917f;  // degrees, east positive
  float timezone = 9.0f;        // hours ahead of UTC
};

// Where the sun stands for `when` (including the parallax correction).
SkyAngles sun_angles(const Observation& when);

// Mitsuba's apparent diameter of the solar disk, in degrees.
inline constexpr double kSunApparentDiameterDegrees = 0.5358;

struct SkyParameters {
  float turbidity = 3.0f;  // [1, 10]
  Rgb albedo{0.2f};        // ground albedo per channel, [0, 1] (Mitsuba's default is 0.2)
  float stretch = 1.0f;    // [1, 2]: squeezes the sky's zenith angles by 1/stretch
  bool extend = false;     // continue the horizon's colour below it, fading out
  float scale = 1.0f;
};

// The sky's RGB radiance in direction `view` for a sun at `sun`. `sun` must be above the
// horizon and the parameters in range (the loader checks; here they are preconditions).
class SkyModel {
 public:
  SkyModel(const SkyParameters& parameters, const SkyAngles& sun);
  Rgb radiance(const SkyAngles& view) const;

 private:
  SkyParameters parameters_;
  SkyAngles sun_;
  double config_[3][9];  // per channel: the model's coefficients A..I at this sun
  double level_[3];      // per channel: the radiance scale at this sun
};

// The `sky` emitter's map: resolution x resolution/2 pixels. `round_trip` evaluates each
// pixel through its unit direction and back (as `sunsky` does), which moves results by a
// few float ulps only.
Image rasterize_sky(const SkyModel& model, int resolution, bool round_trip = false);

// The RGB radiance of the solar disk for a sun at zenith angle `zenith` (radians).
Rgb sun_radiance(float zenith, float turbidity);

// Adds the solar disk to a map as Mitsuba does: a fixed low-discrepancy set of directions
// in a cone of `radius_scale` times the sun's apparent radius around `sun`, each depositing
// its share of the disk's power (radiance times the unscaled disk's solid angle) in the
// pixel it falls into. `radius_scale` must be > 0.
void add_sun(Image& map, const SkyAngles& sun, const Rgb& radiance, float radius_scale);

}  // namespace emlt::sky
