#pragma once
// Lu's deterministic fractional sample counts (thesis 004, section 3.3.2, Eqs. 3.5-3.6) for
// the light half of `direct`'s estimate under `--env-sampler cube-balanced`.
//
// The one-sample light estimate chooses, per sample, a light by power and (for the
// environment) a face with probability mu_f. Eq. 3.5 instead gives each face its expected
// count M_f = mu_f N outright: ceil(M_f) samples from the face's table, all weighted 1 but
// the last, weighted frac(M_f) (Eq. 3.6), so that the weights sum to M_f. Each sample
// contributes f L cos / (mu_f pdf(w | f)) divided by N, so a face's expected total is
// M_f / (mu_f N) times its integral, the integral itself: unbiased, and the faces are
// stratified (no face's share depends on chance).
//
// Generalisation (the thesis has the environment as the only light): the techniques are
// the scene's lights, each with its expected count selection(l) N, except that the
// environment is six techniques, one per face, with selection(env) mu_f N. A sample's MIS
// weight against BSDF sampling is the balance (or power, max) heuristic between
// selection(l) pdf_l(w) and the BSDF's density: as faces are disjoint, the one face whose
// table can draw w is the whole light density there, which is Eq. 3.7's denominator.
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/sampling/cube_balanced_sampler.h"
#include "emlt/scene/scene.h"
#include "emlt/settings/settings.h"

namespace emlt {

// Eq. 3.6 for an expected count M >= 0: ceil(M) samples, the last weighted frac(M) (1 when
// M is whole).
struct FractionalCount {
  int samples = 0;
  double last_weight = 0.0;
};

// Deliberate mistakes for the tests that must notice them.
enum class FractionalCountFault {
  None,
  LastSampleFullWeight,  // frac(M) dropped: every sample weighted 1 (biased up)
  CountFromFaceAlone,    // M_f = mu_f N, forgetting the environment's selection probability
};

FractionalCount fractional_count(double expected,
                                 FractionalCountFault fault = FractionalCountFault::None);

// One technique of the light half: `light` (chosen with `probability` among the lights and,
// for a face, times mu_f) and, for the environment under cube-balanced sampling, `face`
// (-1: the light's own sampling).
struct LightTechnique {
  const Light* light = nullptr;
  int face = -1;
  double probability = 0.0;  // its share of the light samples, selection x mu_f
};
std::vector<LightTechnique> light_techniques(
    const Scene& scene, const EnvironmentSampling& env,
    FractionalCountFault fault = FractionalCountFault::None);

// The light half of the direct estimate at `hit` with N = `samples` light samples shared
// by fractional counts; the sum of the weighted contributions (the caller divides by N, as
// it does the one-sample light samples). Each technique's ceil(M) points are one set of
// `point_set` of that size (independent points for the estimators that are not point sets).
Rgb light_samples_by_fractional_counts(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                       int samples, MisHeuristic heuristic,
                                       const EnvironmentSampling& env, DirectPointSet point_set,
                                       Rng& rng,
                                       FractionalCountFault fault = FractionalCountFault::None);

}  // namespace emlt
