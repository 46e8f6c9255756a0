#include "emlt/scene/environment.h"

#include <algorithm>

#include "emlt/core/frame.h"
#include "emlt/core/warp.h"

namespace emlt {

// ---------------------------------------------------------------------------------------
// EnvironmentLight: direct lighting and emission shared by every sky model.

std::optional<DirectLightSample> EnvironmentLight::sample_direct(const Vec3& ref,
                                                                 const Vec2& u) const {
  float pdf = 0.0f;
  const Vec3 wi = sample_direction(u, &pdf);
  if (!(pdf > 0.0f)) return std::nullopt;
  DirectLightSample sample;
  sample.position = ref + wi;
  sample.normal = Vec3(0.0f);
  sample.wi = wi;
  sample.distance = kInfinity;
  sample.radiance = radiance(wi);
  sample.pdf = pdf;
  return sample;
}

float EnvironmentLight::pdf_direct(const Vec3& ref, const Vec3& p, const Vec3& n,
                                   const Vec3& wi) const {
  (void)ref;
  (void)p;
  (void)n;
  return pdf_direction(wi);
}

// Emission from the sky (pbrt's construction): pick a sky direction w, then a ray origin
// uniformly on the disk of radius R that faces w, centred R away from the scene centre
// towards the sky. Every such ray runs into the scene's bounding sphere along d = -w, so the
// pair (disk point, direction) covers all rays that can reach the scene.
std::optional<EmissionSample> EnvironmentLight::sample_emission(const Vec2& u_position,
                                                                const Vec2& u_direction) const {
  float pdf_sky = 0.0f;
  const Vec3 sky = sample_direction(u_direction, &pdf_sky);
  if (!(pdf_sky > 0.0f)) return std::nullopt;
  const Vec3 direction = -sky;
  EmissionSample sample;
  sample.ray = Ray{disk_.point(sky, u_position), direction, 0.0f, kInfinity};
  sample.normal = direction;
  sample.radiance = radiance(sky);
  sample.pdf_position = disk_.pdf();
  sample.pdf_direction = pdf_sky;
  return sample;
}

void EnvironmentLight::pdf_emission(const Vec3& p, const Vec3& n, const Vec3& w,
                                    float* pdf_position, float* pdf_direction) const {
  (void)p;
  (void)n;
  if (pdf_position) *pdf_position = disk_.pdf();
  if (pdf_direction) *pdf_direction = this->pdf_direction(-w);  // w runs into the scene
}

// ---------------------------------------------------------------------------------------
// ConstantEnvironment

// Power convention (pbrt-v4's): the flux the sky sends through the scene's bounding
// disk, pi R^2 * integral of L over the sphere = pi R^2 * 4 pi * L. The same convention is
// used by EnvironmentMap, so light selection compares the two consistently.
Rgb ConstantEnvironment::power() const {
  return disk_.area() * 4.0f * kPi * radiance_;
}

Vec3 ConstantEnvironment::sample_direction(const Vec2& u, float* pdf) const {
  if (pdf) *pdf = uniform_sphere_pdf();
  return square_to_uniform_sphere(u);
}

float ConstantEnvironment::pdf_direction(const Vec3& w) const {
  (void)w;
  return uniform_sphere_pdf();
}

// ---------------------------------------------------------------------------------------
// EnvironmentMap
//
// Radiance is Mitsuba 0.6's envmap lookup (emitters/envmap.cpp, evalBilinear(0, uv) of
// render/mipmap.h): bilinear interpolation of the level-0 texels, texel (i, j) centred at
// ((i + 0.5) / W, (j + 0.5) / H), repeating in u and clamped in v. (Mitsuba filters
// camera rays with ray differentials by EWA instead, but where a pixel's footprint is
// under one texel, as a lat-long map of ordinary resolution presents it to a camera away
// from the poles, its EWA falls back to this same bilinear lookup. Not reproduced: EWA
// where a pixel covers more than a texel, i.e. directly seen sky of a high-resolution
// map, or close to a pole, where a pixel spans many texel columns.)
//
// Sampling follows Mitsuba's construction, made exact at the poles: pick texel (i, j)
// with probability P_ij proportional to luminance x sin(theta_j) (theta_j at the row's
// centre), then offset the texel centre by a tent-distributed amount in each axis. In
// pixel units the density is then sum_ij P_ij tent(x - i) tent(y - j), which is exactly
// the bilinear interpolation of P at the sample, with the same taps and weights as the
// radiance lookup. Wrapping x around the seam makes it the repeat-in-u interpolation.
// Where a tent leaves the map over a pole, Mitsuba lets theta go negative (the sample
// lands mirrored across the pole, half a map away in phi) although its pdf assumes
// clamping; here the overshoot is reflected back into the same column instead, and the
// reflected tent adds up to a constant across the last half row, which is exactly the
// clamp-in-v interpolation. So the sampled density is the bilinear interpolation of P
// everywhere, and pdf_direction() evaluates exactly that (over the lat-long Jacobian).
//
// The density is positive wherever the radiance is: both blend the same taps with the
// same positive weights, and a tap has P_ij > 0 exactly when its texel is not black
// (positive Rec. 709 weights, sin(theta_j) > 0 at row centres; barring float underflow
// of texels ~1e-38 below the map's total). Negative and non-finite
// texels are clamped to zero at construction (Mitsuba clamps negatives too), so black and
// zero luminance coincide.

namespace {

inline float texel_sin_theta(int row, int height) {
  return std::sin(kPi * (float(row) + 0.5f) / float(height));
}

// Inverse CDF of the tent density 1 - |t| on [-1, 1] (Mitsuba's squareToTent, per axis).
inline float sample_tent(float u) {
  return u < 0.5f ? std::sqrt(2.0f * u) - 1.0f : 1.0f - std::sqrt(2.0f - 2.0f * u);
}

}  // namespace

EnvironmentMap::EnvironmentMap(Image map, float scale, const Mat3& to_world)
    : map_(std::move(map)), scale_(scale), to_world_(to_world),
      to_local_(glm::inverse(to_world)) {
  for (Rgb& texel : map_.pixels) {
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(texel[c]) || texel[c] < 0.0f) texel[c] = 0.0f;
    }
  }
  if (!(scale_ >= 0.0f) || !std::isfinite(scale_)) scale_ = 0.0f;
  const int width = map_.width, height = map_.height;
  if (width <= 0 || height <= 0) return;  // empty map: black sky, never sampled

  // Texel weight = luminance x sin(theta at the row centre), Mitsuba's table: the
  // (u,v) -> direction Jacobian is 2 pi^2 sin(theta), so this makes each texel's
  // probability roughly proportional to its radiance times its solid angle. Exactness
  // does not depend on the choice: pdf_direction() uses the same P.
  // to_world is assumed to be a rotation: a rotation needs no extra Jacobian.
  std::vector<float> row_mass(static_cast<size_t>(height));
  columns_.reserve(size_t(height));
  double weighted_sum[3] = {0.0, 0.0, 0.0};
  double sin_sum = 0.0;
  for (int y = 0; y < height; ++y) {
    const float sin_theta = texel_sin_theta(y, height);
    std::vector<float> weights(static_cast<size_t>(width));
    for (int x = 0; x < width; ++x) {
      const Rgb& texel = map_.at(x, y);
      weights[size_t(x)] = luminance(texel) * sin_theta;
      for (int c = 0; c < 3; ++c) weighted_sum[c] += double(texel[c]) * sin_theta;
      sin_sum += sin_theta;
    }
    columns_.emplace_back(std::move(weights));
    row_mass[size_t(y)] = float(columns_.back().total());
  }
  rows_ = Distribution1D(std::move(row_mass));
  // The probabilities the two-stage discrete choice really has (from the same cdfs), so
  // that the evaluated density is that of the sampler up to float round-off.
  texel_probability_.assign(map_.pixels.size(), 0.0f);
  if (!rows_.empty_mass()) {
    for (int y = 0; y < height; ++y) {
      const double row_pmf = rows_.pmf(size_t(y));
      for (int x = 0; x < width; ++x) {
        texel_probability_[size_t(y) * width + x] =
            float(row_pmf * double(columns_[size_t(y)].pmf(size_t(x))));
      }
    }
  }
  // Solid-angle-weighted mean radiance (midpoint rule in theta, matching the table): used
  // for light selection only, so the few-per-mille difference from the exact integral of
  // the interpolated map does not matter.
  for (int c = 0; c < 3; ++c) {
    average_radiance_[c] = float(scale_ * weighted_sum[c] / std::max(sin_sum, 1e-30));
  }
}

EnvironmentMap::BilinearTaps EnvironmentMap::bilinear_taps(const Vec2& uv) const {
  const int width = map_.width, height = map_.height;
  // Texel centres at (i + 0.5) / size: pixel coordinates are u W - 0.5, v H - 0.5.
  const float x = uv.x * float(width) - 0.5f, y = uv.y * float(height) - 0.5f;
  const float x_floor = std::floor(x), y_floor = std::floor(y);
  const float fx = x - x_floor, fy = y - y_floor;
  const int x0 = int(x_floor), y0 = int(y_floor);
  const auto column = [width](int i) {  // repeat in u (phi is periodic)
    i %= width;
    return size_t(i < 0 ? i + width : i);
  };
  const auto row = [height](int j) { return size_t(std::clamp(j, 0, height - 1)); };  // clamp in v
  const size_t c0 = column(x0), c1 = column(x0 + 1);
  const size_t r0 = row(y0) * size_t(width), r1 = row(y0 + 1) * size_t(width);
  return BilinearTaps{{r0 + c0, r0 + c1, r1 + c0, r1 + c1},
                      {(1.0f - fx) * (1.0f - fy), fx * (1.0f - fy), (1.0f - fx) * fy, fx * fy}};
}

Rgb EnvironmentMap::power() const {
  // Same convention as ConstantEnvironment: pi R^2 * 4 pi * (solid-angle mean radiance).
  return disk_.area() * 4.0f * kPi * average_radiance_;
}

Rgb EnvironmentMap::radiance(const Vec3& w) const {
  if (map_.width <= 0 || map_.height <= 0) return Rgb(0.0f);
  const Vec3 local = to_local_ * w;
  const float length = glm::length(local);
  if (!(length > 0.0f)) return Rgb(0.0f);
  const BilinearTaps taps = bilinear_taps(direction_to_latlong(local / length));
  Rgb sum(0.0f);
  for (int k = 0; k < 4; ++k) sum += taps.weight[k] * map_.pixels[taps.index[k]];
  return scale_ * sum;
}

Vec3 EnvironmentMap::sample_direction(const Vec2& u, float* pdf) const {
  if (!samplable()) {
    if (pdf) *pdf = 0.0f;
    return Vec3(0.0f, 1.0f, 0.0f);
  }
  const int width = map_.width, height = map_.height;
  // u.y picks the row, u.x the column within it (Mitsuba's order); what is left of each
  // number inside its bucket drives the tent offset along that axis.
  float u_row = 0.0f, u_column = 0.0f;
  const size_t row = rows_.sample_discrete(u.y, nullptr, &u_row);
  const size_t column = columns_[row].sample_discrete(u.x, nullptr, &u_column);
  // Pixel coordinates (texel i spans [i, i+1)), centre plus tent offset.
  float x = float(column) + 0.5f + sample_tent(u_column);
  float y = float(row) + 0.5f + sample_tent(u_row);
  // Reflect overshoot past a pole back into the map (see the comment above: this is what
  // makes the density the clamp-in-v interpolation). |overshoot| <= 1/2 < height.
  if (y < 0.0f) y = -y;
  else if (y > float(height)) y = 2.0f * float(height) - y;
  // Wrap across the phi seam: x is within half a texel of [0, width].
  float uu = x / float(width);
  if (uu < 0.0f) uu += 1.0f;
  else if (uu >= 1.0f) uu -= 1.0f;
  const Vec2 uv(uu, std::clamp(y / float(height), 0.0f, 1.0f));
  const Vec3 w = glm::normalize(to_world_ * latlong_to_direction(uv));
  // The density is evaluated from the returned direction: it is continuous, so the
  // (u,v) -> w -> (u,v) round trip changes it only by float round-off, and reporting
  // pdf_direction(w) keeps every consumer (MIS weights, Metropolis acceptance)
  // bit-identical for the same direction.
  if (pdf) *pdf = pdf_direction(w);
  return w;
}

float EnvironmentMap::pdf_direction(const Vec3& w) const {
  if (!samplable()) return 0.0f;
  const Vec3 local = to_local_ * w;
  const float length = glm::length(local);
  if (!(length > 0.0f)) return 0.0f;
  const Vec3 d = local / length;
  // sin(theta) from the direction's horizontal part (not sin(pi v) or sqrt(1 - y^2)):
  // accurate near the poles, where acos and 1 - y^2 lose precision. At the poles the
  // Jacobian vanishes and the density is reported as 0 rather than infinite.
  const float sin_theta = std::sqrt(d.x * d.x + d.z * d.z);
  if (!(sin_theta > 0.0f)) return 0.0f;
  const BilinearTaps taps = bilinear_taps(direction_to_latlong(d));
  float probability = 0.0f;  // bilinear interpolation of P: density per unit pixel area
  for (int k = 0; k < 4; ++k) probability += taps.weight[k] * texel_probability_[taps.index[k]];
  const float pdf = probability * float(map_.width) * float(map_.height) /
                    (2.0f * kPi * kPi * sin_theta);
  return std::isfinite(pdf) ? pdf : 0.0f;
}

}  // namespace emlt
