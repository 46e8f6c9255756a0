// The solar disk: its spectral radiance after the atmosphere (Preetham et al. 1999) turned
// into RGB, and its rasterisation into a lat-long map (emlt/scene/sky.h).
//
// Mitsuba computes both in single precision; the steps below keep its types, and its
// disk uses a fixed (0,2)-sequence of directions, so that the few pixels the sun covers
// receive the same shares here as there.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "emlt/scene/sky.h"
#include "emlt/scene/spectrum.h"

namespace emlt::sky {

namespace {

#include "src/scene/sky/preetham_sun_tables.inc"

constexpr double kPiD = 3.14159265358979323846;

// A tabulated curve as single-precision samples, linear in between, 0 outside (Mitsuba's
// InterpolatedSpectrum, which the sun model evaluates at exact table wavelengths too).
float table(const double* wavelengths, const double* values, int count, float lambda) {
  if (lambda < float(wavelengths[0]) || lambda > float(wavelengths[count - 1])) return 0.0f;
  int i = 0;
  while (float(wavelengths[i]) < lambda) ++i;  // first sample >= lambda
  if (float(wavelengths[i]) == lambda) return float(values[i]);
  const float a = float(wavelengths[i - 1]), b = float(wavelengths[i]);
  const float t = (lambda - a) / (b - a);
  return (1.0f - t) * float(values[i - 1]) + t * float(values[i]);
}

float fast_exp(float x) {
  return float(std::exp(double(x)));
}

// The sun's angular radius in radians (Mitsuba rounds it to float through its degToRad).
float sun_radius() {
  return float(float(kSunApparentDiameterDegrees * 0.5f) * (kPiD / 180.0f));
}

// Van der Corput and Sobol' radical inverses in base 2, single precision: the unscrambled
// (0,2)-sequence Mitsuba draws the disk's directions from.
float van_der_corput(uint32_t n) {
  n = (n << 16) | (n >> 16);
  n = ((n & 0x00ff00ffu) << 8) | ((n & 0xff00ff00u) >> 8);
  n = ((n & 0x0f0f0f0fu) << 4) | ((n & 0xf0f0f0f0u) >> 4);
  n = ((n & 0x33333333u) << 2) | ((n & 0xccccccccu) >> 2);
  n = ((n & 0x55555555u) << 1) | ((n & 0xaaaaaaaau) >> 1);
  return float(n >> 8) / float(1u << 24);  // 24 bits: a float's mantissa
}

float sobol(uint32_t n) {
  uint32_t bits = 0;
  for (uint32_t v = 1u << 31; n != 0; n >>= 1, v ^= v >> 1)
    if (n & 1) bits ^= v;
  return float(bits) / float(1ull << 32);
}

// Tangents of the frame around `n`, chosen as Mitsuba's coordinateSystem chooses them: the
// disk's sample pattern turns with them.
void tangents(const Vec3& n, Vec3& s, Vec3& t) {
  if (std::abs(n.x) > std::abs(n.y)) {
    const float inv = 1.0f / std::sqrt(n.x * n.x + n.z * n.z);
    t = Vec3(n.z * inv, 0.0f, -n.x * inv);
  } else {
    const float inv = 1.0f / std::sqrt(n.y * n.y + n.z * n.z);
    t = Vec3(0.0f, n.z * inv, -n.y * inv);
  }
  s = glm::cross(t, n);
}

}  // namespace

Rgb sun_radiance(float zenith, float turbidity) {
  // Aerosol amount (Angstrom's beta) from turbidity, and the relative optical air mass of
  // Kasten's formula.
  const float beta = 0.04608365822050f * turbidity - 0.04586025928522f;
  const float mass =
      float(1.0f / (std::cos(zenith) +
                    0.15f * std::pow(93.885f - zenith / kPiD * 180.0f, double(-1.253f))));
  spectrum::PiecewiseLinear s;
  for (int i = 0; i < 91; ++i) {  // 350-800 nm in 5 nm steps
    const float lambda = 350.0f + 5.0f * float(i), micrometres = lambda / 1000.0f;
    const float rayleigh = fast_exp(-mass * 0.008735f * std::pow(micrometres, -4.08f));
    const float aerosol = fast_exp(-mass * beta * std::pow(micrometres, -1.3f));
    const float k_o = table(kOzoneWavelengths, kOzoneValues, kOzoneCount, lambda);
    const float ozone = fast_exp(-mass * k_o * 0.35f);  // 0.35 cm of ozone
    const float k_g = table(kMixedGasWavelengths, kMixedGasValues, kMixedGasCount, lambda);
    const float gas = fast_exp(-1.41f * k_g * mass / std::pow(1.0f + 118.93f * k_g * mass, 0.45f));
    const float k_wa =
        table(kWaterVapourWavelengths, kWaterVapourValues, kWaterVapourCount, lambda);
    const float water = 2.0f;  // cm of precipitable water
    const float vapour = fast_exp(-0.2385f * k_wa * water * mass /
                                  std::pow(1.0f + 20.07f * k_wa * water * mass, 0.45f));
    const float solar = table(kSolarWavelengths, kSolarValues, kSolarCount, lambda);
    s.wavelengths.push_back(lambda);
    s.values.push_back(solar * rayleigh * aerosol * ozone * gas * vapour);
  }
  const DVec3 rgb = spectrum::xyz_to_linear_rgb(spectrum::to_xyz(s));
  return glm::max(Rgb(rgb), Rgb(0.0f));
}

void add_sun(Image& map, const SkyAngles& sun, const Rgb& radiance, float radius_scale) {
  const float radius = sun_radius();
  const float cos_cutoff = std::cos(radius * radius_scale);
  // Enough directions for about a thousand per covered pixel, at least 100.
  const size_t pixel_count = size_t(map.width) * size_t(map.width) / 2;
  const float covered = 0.5f * (1.0f - cos_cutoff);
  const size_t count = size_t(std::max(100.0f, float(pixel_count) * covered * 1000.0f));
  // Each direction carries an equal share of the unscaled disk's power (so `radius_scale`
  // keeps the power), as density per unit of lat-long pixel area.
  const Rgb share = radiance * float(2 * kPiD * (1.0f - std::cos(radius))) *
                    float(map.width * map.height) / float(2 * kPiD * kPiD * double(count));
  const Vec3 n = direction_of(sun);
  Vec3 s, t;
  tangents(n, s, t);
  const float to_x = float(map.width / (2 * kPiD)), to_y = float(map.height / kPiD);
  for (size_t i = 0; i < count; ++i) {
    // A uniformly distributed direction of the cone around n.
    const float u = van_der_corput(uint32_t(i)), v = sobol(uint32_t(i));
    const float cos_theta = (1.0f - u) + u * cos_cutoff;
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    const float phi = float(2.0f * kPiD * v);
    const Vec3 local(std::cos(phi) * sin_theta, std::sin(phi) * sin_theta, cos_theta);
    const Vec3 dir = s * local.x + t * local.y + n * local.z;
    // Texels are denser in solid angle towards the poles: divide by sin(zenith).
    const float sin_zenith = std::sqrt(std::max(0.0f, 1.0f - dir.y * dir.y));
    const SkyAngles at = angles_of(dir);
    const int x = std::clamp(int(at.azimuth * to_x), 0, map.width - 1);
    const int y = std::clamp(int(at.zenith * to_y), 0, map.height - 1);
    map.at(x, y) += share / std::max(1e-3f, sin_zenith);
  }
}

}  // namespace emlt::sky
