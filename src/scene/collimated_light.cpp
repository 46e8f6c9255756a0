#include "emlt/scene/collimated_light.h"

namespace emlt {

CollimatedLight::CollimatedLight(const Vec3& origin, const Vec3& travel, const Rgb& power)
    : origin_(origin), travel_(glm::normalize(travel)), power_(power) {}

bool CollimatedLight::along_beam(const Vec3& w) const {
  // The direction from x0 to the point the beam hit, recomputed from the two positions,
  // agrees with the beam to float precision; any other direction is off the beam.
  return glm::dot(w, travel_) > 1.0f - 1e-5f;
}

std::optional<DirectLightSample> CollimatedLight::sample_direct(const Vec3&, const Vec2&) const {
  return std::nullopt;
}

float CollimatedLight::pdf_direct(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const {
  return 0.0f;
}

std::optional<EmissionSample> CollimatedLight::sample_emission(const Vec2&, const Vec2&) const {
  EmissionSample sample;
  sample.ray = Ray{origin_, travel_, 0.0f, kInfinity};
  sample.normal = Vec3(0.0f);
  sample.radiance = power_;
  sample.pdf_position = 1.0f;
  sample.pdf_direction = 1.0f;
  return sample;
}

void CollimatedLight::pdf_emission(const Vec3&, const Vec3&, const Vec3& w, float* pdf_position,
                                   float* pdf_direction) const {
  if (pdf_position) *pdf_position = 1.0f;
  if (pdf_direction) *pdf_direction = along_beam(w) ? 1.0f : 0.0f;
}

Rgb CollimatedLight::emitted(const Vec3&, const Vec3& w) const {
  return along_beam(w) ? power_ : Rgb(0.0f);
}

}  // namespace emlt
