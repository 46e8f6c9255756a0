#pragma once
// A directional light: Mitsuba 0.6's `directional` emitter, parallel light of a given
// irradiance (at normal incidence) arriving from one direction. Its vertex x0 is that
// direction, a point at infinity like the sky's, picked with probability 1 once the light
// is chosen; light tracing starts its rays on a disk facing the direction that covers the
// scene, as the sky's do.
#include "emlt/scene/light.h"
#include "emlt/scene/scene_disk.h"

namespace emlt {

class DirectionalLight final : public Light {
 public:
  // `travel`: the unit direction the light travels in (Mitsuba's `direction`).
  DirectionalLight(const Vec3& travel, const Rgb& irradiance);

  bool is_delta_direction() const override { return true; }
  // The disk emission rays start on must cover the scene: call before the light set is built.
  void set_scene_bounds(const Vec3& center, float radius) { disk_ = SceneDisk{center, radius}; }

  Rgb power() const override;
  std::optional<DirectLightSample> sample_direct(const Vec3& ref, const Vec2& u) const override;
  float pdf_direct(const Vec3& ref, const Vec3& p, const Vec3& n, const Vec3& wi) const override;
  std::optional<EmissionSample> sample_emission(const Vec2& u_position,
                                                const Vec2& u_direction) const override;
  void pdf_emission(const Vec3& p, const Vec3& n, const Vec3& w, float* pdf_position,
                    float* pdf_direction) const override;
  // The irradiance towards the scene when w (pointing from the scene towards the light) is
  // the light's own direction; zero otherwise.
  Rgb emitted(const Vec3& n, const Vec3& w) const override;

  // Unit direction from the scene towards the light.
  const Vec3& towards_light() const { return towards_light_; }

 private:
  Vec3 towards_light_;
  Rgb irradiance_;
  SceneDisk disk_;
};

}  // namespace emlt
