#pragma once
// A point light with an optional spot cone: Mitsuba 0.6's `point` and `spot` emitters.
// The light has a position but no surface, so its vertex x0 lies in the discrete
// (counting) measure: light sampling picks it with probability 1 once the light is chosen,
// no walk can hit it, and the geometry term has no cosine at it. Its "emitted radiance"
// in the path integral is the radiant intensity I(w) (W/sr), which the 1/d^2 of the
// geometry term turns into irradiance at the receiver.
#include "emlt/core/frame.h"
#include "emlt/scene/light.h"
#include "emlt/scene/texture.h"

namespace emlt {

// The spot's beam: full intensity within `beam_width` of the axis, falling linearly in
// angle to zero at `cutoff` (radians), and an optional texture projected over the cone
// (u, v = 0.5 + 0.5 (x, y) / (z tan(cutoff)) in the light's frame).
struct SpotProfile {
  float cutoff = 0.0f;
  float beam_width = 0.0f;
  TexturePtr texture;  // null: white
};

// Known mistakes the tests inject to show they notice them (SceneBuildOptions).
struct DeltaLightFaults {
  // The light sample MIS-weighted against BSDF sampling, as an area light's would be.
  bool mis_weighted_light_sample = false;
  // The point given an area density (of a sphere of radius 0.05 round it) where its
  // emission is sampled, as if it were a small area light.
  bool area_density = false;
};

class PointLight final : public Light {
 public:
  // `frame`: the light's orientation (its z axis is the spot's axis); `spot`: null for an
  // isotropic point light.
  PointLight(const Vec3& position, const Frame& frame, const Rgb& intensity,
             std::optional<SpotProfile> spot, DeltaLightFaults faults = {});

  bool is_delta_position() const override { return true; }
  Rgb power() const override;
  std::optional<DirectLightSample> sample_direct(const Vec3& ref, const Vec2& u) const override;
  float pdf_direct(const Vec3& ref, const Vec3& p, const Vec3& n, const Vec3& wi) const override;
  std::optional<EmissionSample> sample_emission(const Vec2& u_position,
                                                const Vec2& u_direction) const override;
  void pdf_emission(const Vec3& p, const Vec3& n, const Vec3& w, float* pdf_position,
                    float* pdf_direction) const override;
  // The intensity towards world direction w (n is ignored: there is no surface).
  Rgb emitted(const Vec3& n, const Vec3& w) const override;

  Vec3 delta_point() const override { return position_; }

 private:
  Rgb intensity_towards(const Vec3& w_world) const;

  Vec3 position_;
  Frame frame_;
  Rgb intensity_;
  std::optional<SpotProfile> spot_;
  DeltaLightFaults faults_;
  float cos_cutoff_ = -1.0f, cos_beam_ = -1.0f, tan_cutoff_ = 0.0f;
};

}  // namespace emlt
