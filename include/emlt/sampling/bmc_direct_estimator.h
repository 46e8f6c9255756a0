#pragma once
// Bayesian Monte Carlo with spherical Gaussians for the direct lighting of diffuse and glossy
// surfaces (Marques, Bouville, Santos, Bouatouch, "A Spherical Gaussian Framework for Bayesian
// Monte Carlo Rendering of Glossy Surfaces", IEEE TVCG 2013; Marques's thesis, chapter 3).
//
// The reflected radiance is L_o = ∫_H L_i(ω) p(ω) dω with p the BSDF's lobe times the cosine,
// known in closed form, and L_i, unknown, modelled by a Gaussian process whose covariance is a
// spherical Gaussian, k'(ω, ω') = exp((ω·ω' − 1) / l²) (Eq. 18). The posterior mean of the
// integral is a fixed linear combination of the observed radiances (Eq. 14 with the prior mean
// of Eq. 23): Î = L̄ μ + z'ᵗ Q'⁻¹ (Y − L̄ H), Q' = K' + σ'² I, z'_j = ∫_H k'(ω_j, ω) p(ω) dω,
// μ = ∫_H p, L̄ = H Q'⁻¹ Y / H Q'⁻¹ Hᵗ. Its weights are deterministic given the sample set and
// the hyperparameters, so the estimate is biased in the frequentist sense (unbiased only in the
// Bayesian one, [T] §3.4.2); only the `direct` integrator uses it.
//
// Two lobes are modelled:
//   Gaussian  p(ω) = exp(m (ω·a − 1)) on the hemisphere about the normal, a spherical Gaussian
//             about the axis a (the mirror direction): Eq. 19 with w = 1/√m (Eq. 20). z'_j is
//             the hemispherical integral of the product of two spherical Gaussians (Eqs. 21–22).
//   Cosine    p(ω) = cos θ / π about the normal (the Lambertian lobe, exact): z'_j is the
//             kernel's cosine-weighted hemispherical integral, precomputed once per set since the
//             pattern only turns about the normal (Brouillat et al.'s diffuse case).
#include <memory>
#include <optional>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/scene/scene.h"

namespace emlt {

using Vec3d = glm::dvec3;

// The GP's hyperparameters by the fast rule of [BMC] §5.4: noise ratio σ'_n = 0.5 and
// lengthscale l = α / √m with α = 1.25 (m the lobe's sharpness; 1 for the cosine lobe).
struct BmcHyperparameters {
  double noise = 0.5;
  double lengthscale_factor = 1.25;
};

// Over the hemisphere ω·n > 0, with cos_axis = a·n for a unit axis a:
//   area   = ∫_H exp(κ (ω·a − 1)) dω           (the spherical Gaussian integral S_g, Eq. 22)
//   cosine = ∫_H exp(κ (ω·a − 1)) (ω·n) dω
// Computed from an exact one-dimensional form (closed forms where the circles about a lie
// wholly above or below the horizon, Gauss–Legendre panels between), instead of the papers'
// 200 × 200 table.
struct HemisphereMoments {
  double area = 0.0;
  double cosine = 0.0;
};
HemisphereMoments sg_hemisphere_moments(double cos_axis, double kappa);

enum class BmcLobe { Gaussian, Cosine };

// A precomputed sample set: the pattern about its lobe's axis (z), the inverse of Q', and the
// prior mean's weights γ_j / Γ (Eq. 23). Built once per (lobe, n, m, hyperparameters).
struct BmcSampleSet {
  BmcLobe lobe = BmcLobe::Gaussian;
  int count = 0;
  double sharpness = 1.0;    // m (the Gaussian lobe); 1 for the cosine lobe
  double lengthscale = 1.0;  // l
  double noise = 0.5;        // σ'_n
  std::vector<Vec3d> pattern;
  std::vector<double> q_inverse;     // count × count, row-major
  std::vector<double> mean_weights;  // γ_j / Γ, summing to one
  std::vector<double> cosine_z;      // Cosine: z'_j
};

// The pattern of [BMC] Alg. 1 without the optimised polynomial (its coefficients are not
// published): a spherical Fibonacci spiral on the hemisphere about z, z_j = 1 − (j + ½)/n,
// φ_j = j·π(3 − √5), its heights warped onto the lobe (Gaussian: Eq. 25's warp; cosine:
// z ← √z).
std::vector<Vec3d> bmc_pattern(BmcLobe lobe, int count, double sharpness);

// The set for these parameters, from a process-wide cache (built on first use; thread safe).
std::shared_ptr<const BmcSampleSet> bmc_sample_set(BmcLobe lobe, int count, double sharpness,
                                                   const BmcHyperparameters& hyper);
// The same, built afresh with the GP's own pieces given explicitly (tests).
std::shared_ptr<const BmcSampleSet> build_bmc_sample_set(BmcLobe lobe, int count, double sharpness,
                                                         double lengthscale, double noise);

// A quadrature rule at one shading point, in the local frame (z the normal): the directions to
// trace and their weights, ∫_H Y p ≈ Σ_j w_j Y(ω_j). The pattern is turned about the lobe's
// axis by `rotation` turns ([BMC] Alg. 2, step 1) and aligned with `axis` (Gaussian; the
// cosine lobe's axis is the normal). A direction below the horizon keeps its slot with the
// value of the nearest direction above it ([BMC] §4.4): its weight moves there.
struct BmcRule {
  std::vector<Vec3d> directions;
  std::vector<double> weights;
  double lobe_integral = 0.0;  // μ = ∫_H p
  // Every slot of the pattern and its weight before the horizon moved any: the GP's own rule
  // for a function known on the whole sphere.
  std::vector<Vec3d> slots;
  std::vector<double> slot_weights;
};
BmcRule bmc_rule(const BmcSampleSet& set, const Vec3d& axis, double rotation);

// The direct-lighting estimate at `hit` by BMC with `directions` rays in all (shared equally by
// the BSDF's diffuse and glossy lobes), or nothing where the BSDF is not a Lambertian and
// normalised-Phong mix (Bsdf::phong_lobes) and the caller keeps its own estimator. Radiance from
// the environment and from area emitters is what the rays find; delta lights, which no ray finds,
// are added by light sampling.
std::optional<Rgb> estimate_direct_bmc(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                       Rng& rng, int directions, const BmcHyperparameters& hyper);

}  // namespace emlt
