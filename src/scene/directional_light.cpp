#include "emlt/scene/directional_light.h"


namespace emlt {

DirectionalLight::DirectionalLight(const Vec3& travel, const Rgb& irradiance)
    : towards_light_(-glm::normalize(travel)), irradiance_(irradiance) {}

Rgb DirectionalLight::power() const {
  // Only the choice among lights reads this: the flux through the scene's cross-section.
  return irradiance_ * disk_.area();
}

std::optional<DirectLightSample> DirectionalLight::sample_direct(const Vec3& ref,
                                                                 const Vec2&) const {
  DirectLightSample sample;
  sample.position = ref + towards_light_;
  sample.wi = towards_light_;
  sample.distance = kInfinity;
  sample.radiance = irradiance_;
  sample.pdf = 1.0f;
  sample.delta = true;
  return sample;
}

float DirectionalLight::pdf_direct(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const {
  return 0.0f;  // no ray can find one direction
}

std::optional<EmissionSample> DirectionalLight::sample_emission(const Vec2& u_position,
                                                                const Vec2&) const {
  EmissionSample sample;
  sample.ray = Ray{disk_.point(towards_light_, u_position), -towards_light_, 0.0f, kInfinity};
  sample.normal = -towards_light_;
  sample.radiance = irradiance_;
  sample.pdf_position = disk_.pdf();
  sample.pdf_direction = 1.0f;
  return sample;
}

void DirectionalLight::pdf_emission(const Vec3&, const Vec3&, const Vec3& w, float* pdf_position,
                                    float* pdf_direction) const {
  if (pdf_position) *pdf_position = disk_.pdf();
  if (pdf_direction) *pdf_direction = glm::dot(w, -towards_light_) > 1.0f - 1e-6f ? 1.0f : 0.0f;
}

Rgb DirectionalLight::emitted(const Vec3&, const Vec3& w) const {
  return glm::dot(w, towards_light_) > 1.0f - 1e-6f ? irradiance_ : Rgb(0.0f);
}

}  // namespace emlt
