#pragma once
// One direction of the direct-lighting integral at a shading point, drawn by light sampling
// or by BSDF sampling, carrying what any combination of the two strategies needs: the
// single-strategy estimate and both strategies' densities at the direction. The multi-sample
// MIS estimator weights it by a heuristic, the one-sample mixture divides by the mixture
// density, and the second-order split estimates its moments from it.
#include "emlt/sampling/cube_balanced_sampler.h"
#include "emlt/scene/scene.h"

namespace emlt {

struct DirectSample {
  // integrand / own_pdf, the integrand being f_s |cos| L_e V: the estimate the drawing
  // strategy alone would make. Black when the direction brings no light.
  Rgb estimate{0.0f};
  float own_pdf = 0.0f;    // density of the strategy that drew it (solid angle; light selection
                           // included), or a Dirac draw's discrete probability
  float other_pdf = 0.0f;  // the other strategy's density at the same direction
  // Drawn from a Dirac distribution (a delta light, a specular lobe): the other strategy
  // never finds it, and own_pdf is no density, so it weighs by its own strategy alone.
  bool delta = false;
  // The direction drawn (world, unit); zero when the strategy drew none.
  Vec3 wi{0.0f};

  // The integrand itself (estimate * own_pdf); meaningless for a Dirac draw.
  Rgb integrand() const { return estimate * own_pdf; }
};

// Emission arriving at `from` along `direction` from the emitter at `emitter_hit` (the
// environment when null), and light sampling's density for that direction (light selection
// included; left 0 when `with_pdf` is false; `env`: how light sampling at `from` samples the
// environment). Black when nothing emits there.
struct ArrivingEmission {
  Rgb radiance{0.0f};
  float light_pdf = 0.0f;
};
ArrivingEmission arriving_emission(const Scene& scene, const Vec3& from, const Vec3& direction,
                                   const SurfaceHit* emitter_hit, bool with_pdf,
                                   const EnvironmentSampling& env = {});

// A light-sampling direction: `u_select` picks the light (in proportion to power), `u_light`
// the point on it; `env` says how the environment is sampled here.
DirectSample draw_light_direction(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                  float u_select, const Vec2& u_light,
                                  const EnvironmentSampling& env = {});

// A BSDF-sampling direction (radiance transport): `u_lobe` picks the lobe, `u_direction` the
// direction; the ray is traced to what it finds.
DirectSample draw_bsdf_direction(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                 float u_lobe, const Vec2& u_direction,
                                 const EnvironmentSampling& env = {});

}  // namespace emlt
