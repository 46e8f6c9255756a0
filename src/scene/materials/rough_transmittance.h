#pragma once
// Transmittance of a rough dielectric boundary (internal to the engine): the fraction of
// light arriving from direction w (cosine mu to the normal) that a microfacet boundary
// lets through in a single refraction,
//   T(mu) = integral over m of (1 - F(w.m)) G1(w, m) G1(w_t, m) D(m) max(0, w.m) / mu dm,
// with w_t the direction refracted at m. Mitsuba 0.6's `roughplastic` weights its diffuse
// base with T (its rtrans.h, which reads a table precomputed from the same integral)
// instead of the smooth Fresnel transmittance: a rough coating lets far more light in and
// out at grazing angles (GGX, alpha 0.12, eta 1.5: T = 0.60 at mu = 0.02, where the
// smooth 1 - F is 0.11).
//
// Computed here at construction by quadrature over m in the coordinates in which D(m) m.z
// is uniform (a square root substitution removes the GGX tail's singularity), then
// tabulated in sqrt(mu). Agrees with Mitsuba's tables (data/microfacet/*.dat there) to
// 4e-5 (GGX) and 1.6e-4 (Beckmann) from outside; see
// tools/conformance/rough_transmittance_check.py.
#include <utility>
#include <vector>

#include "emlt/scene/materials.h"

namespace emlt {

class RoughTransmittance {
 public:
  // `eta` is n_below / n_above of the boundary (pass 1 / eta for light leaving a coating);
  // alpha is isotropic. `alpha_max` > 0 tabulates roughness over [0, alpha_max] for a
  // textured alpha; 0 tabulates `alpha` alone.
  RoughTransmittance(MicrofacetType type, float eta, float alpha, float alpha_max = 0.0f);

  // T(mu) for 0 <= mu <= 1 and the tabulated alpha (nearest nodes interpolated).
  float operator()(float mu, float alpha) const;
  // The cosine-weighted hemispherical average 2 integral_0^1 T(mu) mu dmu, which is 1
  // minus the boundary's diffuse reflectance (Fdr) as light from inside a coating sees it.
  float diffuse(float alpha) const;

  // The integral for one direction, by a rule of `nodes` x `nodes` points (exposed for
  // tests; construction uses it).
  static double integrate(MicrofacetType type, float alpha, float eta, double mu, int nodes);
  // 2 integral_0^1 T(mu) mu dmu, split at the critical angle when eta < 1.
  static double integrate_diffuse(MicrofacetType type, float alpha, float eta, int mu_nodes,
                                  int nodes);

 private:
  // Position of alpha among the alpha nodes: index and fraction.
  std::pair<int, float> alpha_position(float alpha) const;

  std::vector<float> alphas_;   // alpha nodes
  std::vector<float> table_;    // [alpha node][mu node], mu = (i / (n - 1))^2
  std::vector<float> diffuse_;  // per alpha node
};

}  // namespace emlt
