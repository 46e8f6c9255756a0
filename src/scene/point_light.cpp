#include "emlt/scene/point_light.h"

#include "emlt/core/warp.h"

namespace emlt {

namespace {
// DeltaLightFaults::area_density: the density of a uniform point on a sphere of radius 0.05.
constexpr float kFaultyAreaDensity = 1.0f / (4.0f * 3.14159265f * 0.05f * 0.05f);
}  // namespace

PointLight::PointLight(const Vec3& position, const Frame& frame, const Rgb& intensity,
                       std::optional<SpotProfile> spot, DeltaLightFaults faults)
    : position_(position),
      frame_(frame),
      intensity_(intensity),
      spot_(std::move(spot)),
      faults_(faults) {
  if (spot_) {
    cos_cutoff_ = std::cos(spot_->cutoff);
    cos_beam_ = std::cos(spot_->beam_width);
    tan_cutoff_ = std::tan(spot_->cutoff);
  }
}

Rgb PointLight::intensity_towards(const Vec3& w_world) const {
  if (!spot_) return intensity_;
  const Vec3 d = frame_.to_local(w_world);
  if (d.z <= cos_cutoff_) return Rgb(0.0f);
  Rgb value = intensity_;
  if (spot_->texture) {
    const Vec2 uv(0.5f + 0.5f * d.x / (d.z * tan_cutoff_), 0.5f + 0.5f * d.y / (d.z * tan_cutoff_));
    value *= spot_->texture->eval(uv);
  }
  if (d.z >= cos_beam_) return value;
  // Linear in the angle between the beam's edge and the cutoff.
  const float angle = std::acos(glm::clamp(d.z, -1.0f, 1.0f));
  return value * ((spot_->cutoff - angle) / (spot_->cutoff - spot_->beam_width));
}

Rgb PointLight::power() const {
  // Only the choice among lights reads this; the spot's cone bounds its flux.
  const float solid_angle = spot_ ? kTwoPi * (1.0f - cos_cutoff_) : 4.0f * kPi;
  return intensity_ * solid_angle;
}

std::optional<DirectLightSample> PointLight::sample_direct(const Vec3& ref, const Vec2&) const {
  const Vec3 to_light = position_ - ref;
  const float distance_squared = glm::dot(to_light, to_light);
  if (!(distance_squared > 0.0f) || !std::isfinite(distance_squared)) return std::nullopt;
  const float distance = std::sqrt(distance_squared);
  DirectLightSample sample;
  sample.position = position_;
  sample.normal = Vec3(0.0f);
  sample.wi = to_light / distance;
  sample.distance = distance;
  // The discrete choice of the one point: density 1, and the arriving "radiance" is the
  // irradiance at normal incidence, I / d^2.
  sample.radiance = intensity_towards(-sample.wi) / distance_squared;
  sample.pdf = 1.0f;
  sample.delta = !faults_.mis_weighted_light_sample;
  if (is_black(sample.radiance)) return std::nullopt;
  return sample;
}

float PointLight::pdf_direct(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const {
  return 0.0f;  // no ray can hit a point
}

std::optional<EmissionSample> PointLight::sample_emission(const Vec2&,
                                                          const Vec2& u_direction) const {
  EmissionSample sample;
  const Vec3 local = spot_ ? square_to_uniform_cone(u_direction, cos_cutoff_)
                           : square_to_uniform_sphere(u_direction);
  sample.ray = Ray{position_, frame_.to_world(local), 0.0f, kInfinity};
  sample.normal = Vec3(0.0f);
  sample.radiance = intensity_towards(sample.ray.direction);
  sample.pdf_position = faults_.area_density ? kFaultyAreaDensity : 1.0f;
  sample.pdf_direction = spot_ ? uniform_cone_pdf(cos_cutoff_) : uniform_sphere_pdf();
  return sample;
}

void PointLight::pdf_emission(const Vec3&, const Vec3&, const Vec3& w, float* pdf_position,
                              float* pdf_direction) const {
  if (pdf_position) *pdf_position = faults_.area_density ? kFaultyAreaDensity : 1.0f;
  if (pdf_direction) {
    if (!spot_)
      *pdf_direction = uniform_sphere_pdf();
    else
      *pdf_direction = frame_.to_local(w).z > cos_cutoff_ ? uniform_cone_pdf(cos_cutoff_) : 0.0f;
  }
}

Rgb PointLight::emitted(const Vec3&, const Vec3& w) const {
  return intensity_towards(w);
}

}  // namespace emlt
