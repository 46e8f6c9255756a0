#pragma once
// A collimated beam: Mitsuba 0.6's `collimated` emitter, power P leaving one point along
// one direction. Its vertex x0 is a point (no cosine at it, like a point light's) whose
// emission is a Dirac lobe: the vertex x1 the beam reaches follows from x0, with the
// discrete probability 1, which the path layer converts to area like a specular bounce's
// (vertex.h), so f/p of the first segment is P over the light's selection probability.
// No light sample can reach x0 from anywhere else and no walk can hit it: only light
// tracing renders the beam, as in Mitsuba (its path tracer's image of a beam is black).
#include "emlt/core/frame.h"
#include "emlt/scene/light.h"

namespace emlt {

class CollimatedLight final : public Light {
 public:
  // `travel`: the unit direction of the beam.
  CollimatedLight(const Vec3& origin, const Vec3& travel, const Rgb& power);

  bool is_delta_position() const override { return true; }
  bool is_delta_direction() const override { return true; }
  Vec3 delta_point() const override { return origin_; }

  Rgb power() const override { return power_; }
  // None: from a point off the beam the light cannot be seen.
  std::optional<DirectLightSample> sample_direct(const Vec3& ref, const Vec2& u) const override;
  float pdf_direct(const Vec3& ref, const Vec3& p, const Vec3& n, const Vec3& wi) const override;
  std::optional<EmissionSample> sample_emission(const Vec2& u_position,
                                                const Vec2& u_direction) const override;
  // The discrete probabilities 1 of the point and of the beam's direction.
  void pdf_emission(const Vec3& p, const Vec3& n, const Vec3& w, float* pdf_position,
                    float* pdf_direction) const override;
  // The power along the beam's own direction, zero along any other.
  Rgb emitted(const Vec3& n, const Vec3& w) const override;

  const Vec3& travel() const { return travel_; }

 private:
  bool along_beam(const Vec3& w) const;

  Vec3 origin_, travel_;
  Rgb power_;
};

}  // namespace emlt
