// The sun's place in the sky from date, time and location, and the spherical coordinates
// of the sky's local frame (emlt/scene/sky.h).
//
// Everything here repeats Mitsuba 0.6's arithmetic type for type (single-precision inputs
// and results, double-precision intermediate steps, the same integer divisions), because
// the maps it feeds are compared with Mitsuba's texel for texel.
#include <algorithm>
#include <cmath>

#include "emlt/scene/sky.h"

namespace emlt::sky {

namespace {

constexpr double kPiD = 3.14159265358979323846;

// Degrees to radians as Mitsuba's single-precision build does it (the product in double,
// rounded once).
float radians(float degrees) {
  return float(degrees * (kPiD / 180.0f));
}

}  // namespace

Vec3 direction_of(const SkyAngles& angles) {
  const float sin_theta = std::sin(angles.zenith), cos_theta = std::cos(angles.zenith);
  const float sin_phi = std::sin(angles.azimuth), cos_phi = std::cos(angles.azimuth);
  return Vec3(sin_phi * sin_theta, cos_theta, -cos_phi * sin_theta);
}

SkyAngles angles_of(const Vec3& direction) {
  float azimuth = std::atan2(direction.x, -direction.z);
  if (azimuth < 0.0f) azimuth = float(azimuth + 2 * kPiD);
  const float zenith = std::acos(std::clamp(direction.y, -1.0f, 1.0f));
  return SkyAngles{zenith, azimuth};
}

SkyAngles sun_angles(const Observation& when) {
  // Universal time in decimal hours, then days since JD 2451545.0 (noon UT, 1 Jan 2000)
  // through the Julian day number of the civil date (Fliegel & Van Flandern's integer
  // formula, C division truncating towards zero).
  const double hours_ut = (when.hour - when.timezone) + (when.minute + when.second / 60.0) / 60.0;
  const int a = (when.month - 14) / 12;
  const int julian_day_number = (1461 * (when.year + 4800 + a)) / 4 +
                                (367 * (when.month - 2 - 12 * a)) / 12 -
                                (3 * ((when.year + 4900 + a) / 100)) / 4 + when.day - 32075;
  const double days = (double(julian_day_number) - 0.5 + hours_ut / 24.0) - 2451545.0;

  // Ecliptic coordinates (radians, not reduced to [0, 2 pi)).
  const double omega = 2.1429 - 0.0010394594 * days;
  const double mean_longitude = 4.8950630 + 0.017202791698 * days;
  const double mean_anomaly = 6.2400600 + 0.0172019699 * days;
  const double ecliptic_longitude = mean_longitude + 0.03341607 * std::sin(mean_anomaly) +
                                    0.00034894 * std::sin(2 * mean_anomaly) - 0.0001134 -
                                    0.0000203 * std::sin(omega);
  const double obliquity = 0.4090928 - 6.2140e-9 * days + 0.0000396 * std::cos(omega);

  // Celestial coordinates.
  const double sin_longitude = std::sin(ecliptic_longitude);
  double right_ascension =
      std::atan2(std::cos(obliquity) * sin_longitude, std::cos(ecliptic_longitude));
  if (right_ascension < 0.0) right_ascension += 2 * kPiD;
  const double declination = std::asin(std::sin(obliquity) * sin_longitude);

  // Local coordinates: zenith angle and azimuth (from north, through east).
  const double sidereal_hours = 6.6974243242 + 0.0657098283 * days + hours_ut;
  const double local_sidereal = radians(float(sidereal_hours * 15 + when.longitude));
  const double latitude = radians(when.latitude);
  const double cos_latitude = std::cos(latitude), sin_latitude = std::sin(latitude);
  const double hour_angle = local_sidereal - right_ascension;
  const double cos_hour_angle = std::cos(hour_angle);
  double zenith = std::acos(cos_latitude * cos_hour_angle * std::cos(declination) +
                            std::sin(declination) * sin_latitude);
  double azimuth = std::atan2(-std::sin(hour_angle),
                              std::tan(declination) * cos_latitude - sin_latitude * cos_hour_angle);
  if (azimuth < 0.0) azimuth += 2 * kPiD;
  // Parallax: the observer stands on the earth's surface, not at its centre
  // (mean earth radius over the astronomical unit, both in km).
  zenith += (6371.01 / 149597890.0) * std::sin(zenith);
  return SkyAngles{float(zenith), float(azimuth)};
}

}  // namespace emlt::sky
