#pragma once
// Emitter contract shared by every integrator. Densities are returned in the measure each
// caller needs: solid angle at the receiving point for direct lighting, area (position) x
// solid angle (direction) for emission. The environment uses directions only; its
// "position" density for emission is over a disk covering the scene.
#include <memory>
#include <optional>

#include "emlt/core/math.h"
#include "emlt/scene/ray.h"

namespace emlt {

class Light;

// A point on a light chosen as seen from a receiving point `ref`.
struct DirectLightSample {
  Vec3 position{0.0f};   // on the light (for the environment: ref + wi, unused)
  Vec3 normal{0.0f};     // light's surface normal (zero for the environment)
  Vec3 wi{0.0f};         // unit direction ref -> light
  float distance = kInfinity;  // kInfinity for the environment
  Rgb radiance{0.0f};    // emitted radiance arriving at ref along -wi
  float pdf = 0.0f;      // solid angle density at ref (light selection not included)
  // A delta light's one point or direction: `pdf` is the discrete probability 1 and
  // `radiance` the irradiance it delivers at normal incidence; BSDF sampling can never
  // find it, so it takes no MIS weight.
  bool delta = false;
};

// A ray leaving a light, as light tracing starts it.
struct EmissionSample {
  Ray ray;               // origin on the light, unit direction into the scene
  Vec3 normal{0.0f};     // surface normal (for the environment: the ray direction)
  Rgb radiance{0.0f};    // emitted radiance along the ray
  float pdf_position = 0.0f;   // area density of the origin
  float pdf_direction = 0.0f;  // solid angle density of the direction
};

class Light {
 public:
  virtual ~Light() = default;

  // Total emitted flux (used to choose lights in proportion to power).
  virtual Rgb power() const = 0;
  // The scene's sky, which rays leaving the scene see.
  virtual bool is_environment() const { return false; }
  // Delta lights (Mitsuba's point, spot and directional emitters): a position or a
  // direction that only light sampling can pick, never a ray.
  virtual bool is_delta_position() const { return false; }
  virtual bool is_delta_direction() const { return false; }
  bool is_delta() const { return is_delta_position() || is_delta_direction(); }
  // A light at infinity: the sky, or a directional light. Its x0 is a direction.
  bool at_infinity() const {
    return is_environment() || (is_delta_direction() && !is_delta_position());
  }
  // A delta-position light's one point (its vertex x0 is there and nowhere else).
  virtual Vec3 delta_point() const { return Vec3(0.0f); }

  virtual std::optional<DirectLightSample> sample_direct(const Vec3& ref, const Vec2& u) const = 0;
  // Solid angle density at `ref` of sample_direct producing the point `p` (normal `n`)
  // reached along the unit direction `wi` from ref. For the environment p, n are ignored.
  virtual float pdf_direct(const Vec3& ref, const Vec3& p, const Vec3& n, const Vec3& wi) const = 0;

  virtual std::optional<EmissionSample> sample_emission(const Vec2& u_position,
                                                        const Vec2& u_direction) const = 0;
  // Densities of sample_emission producing origin p (normal n) and direction w.
  virtual void pdf_emission(const Vec3& p, const Vec3& n, const Vec3& w, float* pdf_position,
                            float* pdf_direction) const = 0;

  // Radiance leaving the light at a point with normal n in direction w (area lights), or
  // arriving from direction w (environment: w points away from the scene).
  virtual Rgb emitted(const Vec3& n, const Vec3& w) const = 0;

  int index = -1;  // position in the scene's LightSet, set when the set is built
};

using LightPtr = std::unique_ptr<Light>;

// An emissive triangle: uniform area sampling, one-sided cosine emission.
class TriangleLight final : public Light {
 public:
  TriangleLight(const Vec3& a, const Vec3& b, const Vec3& c, const Rgb& radiance);
  Rgb power() const override;
  std::optional<DirectLightSample> sample_direct(const Vec3& ref, const Vec2& u) const override;
  float pdf_direct(const Vec3& ref, const Vec3& p, const Vec3& n, const Vec3& wi) const override;
  std::optional<EmissionSample> sample_emission(const Vec2& u_position,
                                                const Vec2& u_direction) const override;
  void pdf_emission(const Vec3& p, const Vec3& n, const Vec3& w, float* pdf_position,
                    float* pdf_direction) const override;
  Rgb emitted(const Vec3& n, const Vec3& w) const override;

  float area() const { return area_; }
  const Vec3& normal() const { return normal_; }

 private:
  Vec3 a_, b_, c_, normal_;
  float area_;
  Rgb radiance_;
};

}  // namespace emlt
