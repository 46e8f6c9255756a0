#pragma once
// Environment emitters: a constant colour, or a lat-long map looked up by bilinear
// interpolation (Mitsuba 0.6's envmap) and importance-sampled by a texel table over
// luminance x sin(theta) convolved with a tent, whose density is the bilinear
// interpolation of that table. The sampler's pdf and pdf_direction() agree exactly (same
// table, same Jacobian), which MIS and MLT require.
#include "emlt/core/distribution.h"
#include "emlt/image/image.h"
#include "emlt/scene/light.h"
#include "emlt/scene/scene_disk.h"

namespace emlt {

class EnvironmentLight : public Light {
 public:
  bool is_environment() const override { return true; }

  // Radiance arriving from world direction w (w points from the scene to the sky).
  virtual Rgb radiance(const Vec3& w) const = 0;
  // Importance sampling of directions (solid angle density).
  virtual Vec3 sample_direction(const Vec2& u, float* pdf) const = 0;
  virtual float pdf_direction(const Vec3& w) const = 0;

  // The scene's bounding sphere: emission rays start on a disk of this radius.
  void set_scene_bounds(const Vec3& center, float radius) { disk_ = SceneDisk{center, radius}; }

  std::optional<DirectLightSample> sample_direct(const Vec3& ref, const Vec2& u) const override;
  float pdf_direct(const Vec3& ref, const Vec3& p, const Vec3& n, const Vec3& wi) const override;
  std::optional<EmissionSample> sample_emission(const Vec2& u_position,
                                                const Vec2& u_direction) const override;
  void pdf_emission(const Vec3& p, const Vec3& n, const Vec3& w, float* pdf_position,
                    float* pdf_direction) const override;
  Rgb emitted(const Vec3& n, const Vec3& w) const override { (void)n; return radiance(w); }

 protected:
  SceneDisk disk_;
};

class ConstantEnvironment final : public EnvironmentLight {
 public:
  explicit ConstantEnvironment(const Rgb& radiance) : radiance_(radiance) {}
  Rgb power() const override;
  Rgb radiance(const Vec3&) const override { return radiance_; }
  Vec3 sample_direction(const Vec2& u, float* pdf) const override;
  float pdf_direction(const Vec3& w) const override;

 private:
  Rgb radiance_;
};

class EnvironmentMap final : public EnvironmentLight {
 public:
  // `to_world` rotates map directions into the world; `scale` multiplies every texel.
  EnvironmentMap(Image map, float scale, const Mat3& to_world);
  Rgb power() const override;
  Rgb radiance(const Vec3& w) const override;
  Vec3 sample_direction(const Vec2& u, float* pdf) const override;
  float pdf_direction(const Vec3& w) const override;

  const Image& map() const { return map_; }

 private:
  // The four texels (row-major indices) a bilinear lookup at lat-long (u, v) blends, and
  // their weights; radiance and sampling density both interpolate through this.
  struct BilinearTaps {
    size_t index[4];
    float weight[4];
  };
  BilinearTaps bilinear_taps(const Vec2& uv) const;
  bool samplable() const { return !rows_.empty_mass() && scale_ > 0.0f; }

  Image map_;
  float scale_;
  Mat3 to_world_, to_local_;
  Distribution1D rows_;                   // marginal over rows
  std::vector<Distribution1D> columns_;   // one conditional per row
  std::vector<float> texel_probability_;  // P(texel) of the discrete choice, row-major
  Rgb average_radiance_{0.0f};
};

}  // namespace emlt
