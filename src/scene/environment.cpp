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
  const Frame disk_frame(direction);
  const Vec2 disk = square_to_uniform_disk_concentric(u_position);
  const Vec3 origin = scene_center_ + scene_radius_ * (sky + disk.x * disk_frame.s +
                                                       disk.y * disk_frame.t);
  EmissionSample sample;
  sample.ray = Ray{origin, direction, 0.0f, kInfinity};
  sample.normal = direction;
  sample.radiance = radiance(sky);
  sample.pdf_position = 1.0f / (kPi * scene_radius_ * scene_radius_);
  sample.pdf_direction = pdf_sky;
  return sample;
}

void EnvironmentLight::pdf_emission(const Vec3& p, const Vec3& n, const Vec3& w,
                                    float* pdf_position, float* pdf_direction) const {
  (void)p;
  (void)n;
  if (pdf_position) *pdf_position = 1.0f / (kPi * scene_radius_ * scene_radius_);
  if (pdf_direction) *pdf_direction = this->pdf_direction(-w);  // w runs into the scene
}

// ---------------------------------------------------------------------------------------
// ConstantEnvironment

// Power convention (pbrt-v4's): the flux the sky sends through the scene's bounding
// disk, pi R^2 * integral of L over the sphere = pi R^2 * 4 pi * L. The same convention is
// used by EnvironmentMap, so light selection compares the two consistently.
Rgb ConstantEnvironment::power() const {
  return kPi * scene_radius_ * scene_radius_ * 4.0f * kPi * radiance_;
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
// Design choice: radiance lookup is nearest-texel, and texels of zero luminance get zero
// sampling probability (no floor). The sampled density is then positive exactly where the
// looked-up radiance is non-zero, so environment sampling alone is an unbiased estimator
// of any integral of the map. Bilinear lookup would smear bright texels into black
// neighbours that the table never samples (bias for light-only strategies such as BDPT's
// s=1 connections), and a probability floor would only trade that bias for variance.
// Negative and non-finite texels are clamped to zero at construction, so "zero luminance"
// and "black" coincide (the Rec. 709 weights are all positive).

namespace {

inline float texel_sin_theta(int row, int height) {
  return std::sin(kPi * (float(row) + 0.5f) / float(height));
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

  // Texel weight = luminance x sin(theta at the texel centre): the (u,v) -> direction
  // Jacobian is 2 pi^2 sin(theta), so this makes each texel's probability proportional to
  // its radiance times its solid angle. Within a texel (u,v) is uniform, so the exact
  // solid-angle density is the table's (u,v) density over 2 pi^2 sin(theta) of the
  // direction itself, which is what pdf_direction() computes.
  // to_world is assumed to be a rotation: a rotation needs no extra Jacobian.
  std::vector<float> weights(size_t(width) * size_t(height));
  double weighted_sum[3] = {0.0, 0.0, 0.0};
  double sin_sum = 0.0;
  for (int y = 0; y < height; ++y) {
    const float sin_theta = texel_sin_theta(y, height);
    for (int x = 0; x < width; ++x) {
      const Rgb& texel = map_.at(x, y);
      weights[size_t(y) * width + x] = luminance(texel) * sin_theta;
      for (int c = 0; c < 3; ++c) weighted_sum[c] += double(texel[c]) * sin_theta;
      sin_sum += sin_theta;
    }
  }
  distribution_ = Distribution2D(weights, size_t(width), size_t(height));
  // Solid-angle-weighted mean radiance (midpoint rule in theta, matching the table).
  for (int c = 0; c < 3; ++c) {
    average_radiance_[c] = float(scale_ * weighted_sum[c] / std::max(sin_sum, 1e-30));
  }
}

Rgb EnvironmentMap::power() const {
  // Same convention as ConstantEnvironment: pi R^2 * 4 pi * (solid-angle mean radiance).
  return kPi * scene_radius_ * scene_radius_ * 4.0f * kPi * average_radiance_;
}

Rgb EnvironmentMap::radiance(const Vec3& w) const {
  if (map_.width <= 0 || map_.height <= 0) return Rgb(0.0f);
  const Vec3 local = to_local_ * w;
  const float length = glm::length(local);
  if (!(length > 0.0f)) return Rgb(0.0f);
  const Vec2 uv = direction_to_latlong(local / length);
  const int x = std::clamp(int(uv.x * float(map_.width)), 0, map_.width - 1);
  const int y = std::clamp(int(uv.y * float(map_.height)), 0, map_.height - 1);
  return scale_ * map_.at(x, y);
}

Vec3 EnvironmentMap::sample_direction(const Vec2& u, float* pdf) const {
  if (distribution_.empty_mass() || scale_ <= 0.0f) {
    if (pdf) *pdf = 0.0f;
    return Vec3(0.0f, 1.0f, 0.0f);
  }
  float pdf_uv = 0.0f;
  const Vec2 uv = distribution_.sample(u, &pdf_uv);
  const Vec3 w = glm::normalize(to_world_ * latlong_to_direction(uv));
  // The density is re-evaluated from the returned direction rather than from (u,v): the
  // two agree except within float round-off of a texel edge, where the (u,v) -> w -> (u,v)
  // round trip may land in the neighbouring texel. Reporting pdf_direction(w) keeps every
  // consumer (MIS weights, Metropolis acceptance) bit-identical for the same direction.
  if (pdf) *pdf = pdf_uv > 0.0f ? pdf_direction(w) : 0.0f;
  return w;
}

float EnvironmentMap::pdf_direction(const Vec3& w) const {
  if (distribution_.empty_mass() || scale_ <= 0.0f) return 0.0f;
  const Vec3 local = to_local_ * w;
  const float length = glm::length(local);
  if (!(length > 0.0f)) return 0.0f;
  const Vec3 d = local / length;
  const Vec2 uv = direction_to_latlong(d);
  // sin(theta) from the direction's horizontal part (not sin(pi v) or sqrt(1 - y^2)):
  // accurate near the poles, where acos and 1 - y^2 lose precision. At the poles the
  // Jacobian vanishes and the density is reported as 0 rather than infinite.
  const float sin_theta = std::sqrt(d.x * d.x + d.z * d.z);
  if (!(sin_theta > 0.0f)) return 0.0f;
  const float v = std::min(uv.y, kOneMinusEpsilon);
  const float pdf_uv = distribution_.pdf(Vec2(uv.x, v));
  const float pdf = pdf_uv / (2.0f * kPi * kPi * sin_theta);
  return std::isfinite(pdf) ? pdf : 0.0f;
}

}  // namespace emlt
