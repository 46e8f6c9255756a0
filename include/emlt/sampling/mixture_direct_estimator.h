#pragma once
// Direct lighting as one-sample MIS from the defensive mixture of light and BSDF sampling,
// alpha p_L + (1 - alpha) p_B (Lu's thesis 004, Eq. 5.3; alpha is the light share), and
// Lu's two-step online estimator that picks alpha by the second-order rule first (Eq. 5.6).
//
// A shading point's budget is counted in directions (rays traced towards light), so that
// --direct-samples n buys the same 2n directions as the multi-sample estimator's n light
// and n BSDF samples. Each direction's strategy is chosen by a stratified uniform,
// (i + xi) / n < alpha, so that exactly floor or ceil of alpha n directions come from the
// lights: every direction is still marginally a draw from the mixture (the estimate is
// unbiased for any fixed alpha), and at alpha = 1/2 with an even n the estimate is the
// balance heuristic's with n/2 samples of each strategy, as Eq. 5.3 says.
#include "emlt/core/rng.h"
#include "emlt/sampling/cube_balanced_sampler.h"
#include "emlt/sampling/second_order_alpha.h"
#include "emlt/scene/scene.h"

namespace emlt {

// The light share that a shading point's BSDF leaves open: none where light sampling can
// never find the integrand (a purely specular BSDF), `alpha` otherwise.
double effective_light_share(const SurfaceHit& hit, double alpha);

// (1/n) sum f / (alpha p_L + (1 - alpha) p_B) over `directions` mixture draws; a Dirac draw
// divides by its strategy's probability alone (alpha or 1 - alpha). alpha in [0, 1]; at 0
// or 1 one strategy is dropped, and light only it could find is lost.
// `env` (here and below): how light sampling samples the environment at this point.
Rgb estimate_direct_mixture(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, Rng& rng,
                            double alpha, int directions, const EnvironmentSampling& env = {});

// The pilot of Eq. 5.6: L_{M/2,M/2}, M = `directions` (even) drawn half by each strategy and
// weighted by the balance heuristic (Eq. 5.2), while the same directions' Eq. 5.5 terms go
// to `moments` (may be null).
Rgb estimate_direct_pilot(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, Rng& rng,
                          int directions, SecondOrderAlpha* moments,
                          const EnvironmentSampling& env = {});

struct SecondOrderSplit {
  double pilot = 0.5;    // share of the directions spent on the pilot (Lu's M / (M + N))
  double clamp = 0.025;  // alpha kept within [clamp, 1 - clamp] (Lu's Fig. 5.4)
};

// Lu's online estimator (section 5.5.1, Eq. 5.6): M pilot directions estimate alpha and
// L_{M/2,M/2}, the remaining N directions L_{alpha N,(1-alpha)N} at that alpha, combined as
// M/(M+N) L_pilot + N/(M+N) L_alpha. Unbiased: the second estimate is unbiased at whatever
// alpha the first chose, and the combination's weights are fixed. M is the even number
// nearest pilot * directions (at least 2). `alpha_used` (may be null) receives alpha. At a
// purely specular BSDF every direction is the BSDF's (alpha 0) and there is no pilot.
Rgb estimate_direct_second_order(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                 Rng& rng, int directions, const SecondOrderSplit& split,
                                 double* alpha_used = nullptr, const EnvironmentSampling& env = {});

}  // namespace emlt
