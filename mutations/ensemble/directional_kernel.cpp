// Directional transition kernel of Ensemble MLT (section 3.2): a von Mises-Fisher (vMF)
// distribution fitted to weighted guide directions, recentred on the current direction.
//
// Fit. Guide directions w_n (e.g. x_j -> v^n_{j+1}, or the guides' directions toward the
// environment) get weights in the manner of eq. 11: w(n) ~ context(n) * S(w, w_n), where
// context(n) carries the similarity of unperturbed vertices and S(w, w_n) (optional) the
// similarity of the current direction to the guide's, with unit vectors as points. The
// weighted mean resultant R = sum w(n) w_n gives the mean direction R/|R| and the mean
// resultant length r = |R|; the concentration comes from Banerjee et al.'s approximation on
// S^2, kappa = r (3 - r^2) / (1 - r^2), scaled and clamped. Recentring discards the fitted
// mean: the proposal is vMF(w, kappa(w)), so the kernel adapts its width (and only its
// width) to the spread of the guides near the current state.
//
// Ratio. vMF is symmetric in its argument and mean, so with the same kappa the kernel
// would be symmetric. But kappa depends on the state through the weights: the reverse move
// uses kappa(w') refitted at the proposed direction, and
//     T(w' -> w) / T(w -> w') = vMF(w | w', kappa(w')) / vMF(w' | w, kappa(w)),
// both evaluated at the same cosine w . w'. When the weights do not depend on the
// perturbed direction (context only), kappa(w') = kappa(w) and the ratio is exactly 1.
// The fallback (effective number of guides too small, or no usable weight) uses a fixed
// fallback_concentration; being a function of (w, guides) it is re-decided at w'.
//
// vMF on S^2: density kappa / (4 pi sinh kappa) e^{kappa mu.w}
//           = kappa / (2 pi (1 - e^{-2 kappa})) e^{kappa (mu.w - 1)}   (no overflow),
// sampled by inverting the CDF of the cosine: w = 1 + log(u + (1 - u) e^{-2 kappa}) / kappa.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "emlt/core/frame.h"
#include "mutations/ensemble/kernels.h"

namespace emlt::ensemble {

namespace {

constexpr double kPiDouble = 3.14159265358979323846;
constexpr double kTwoPiDouble = 2.0 * kPiDouble;
// Below this kappa the vMF is uniform to double precision in the formulas used here.
constexpr double kUniformConcentration = 1e-8;

}  // namespace

double vmf_concentration_from_resultant(double mean_resultant_length) {
  const double r = std::clamp(mean_resultant_length, 0.0, 1.0);
  if (r >= 1.0) return std::numeric_limits<double>::infinity();
  return r * (3.0 - r * r) / (1.0 - r * r);
}

VmfFit fit_vmf(const Vec3& current, const GuideSet& directions, const DirectionalParams& params) {
  VmfFit fit;
  fit.concentration = params.fallback_concentration;
  const size_t count = directions.points.size();
  if (count == 0) return fit;

  GuideBuffer<double> weight_buffer(count);
  const std::span<double> weights = weight_buffer.span();
  const Vec3 unit_current(glm::normalize(DVec3(current)));
  const NormalisedWeights normalised =
      guide_weights(unit_current, directions,
                    params.weight_by_direction_similarity ? &params.similarity : nullptr, weights);
  fit.effective_guides = normalised.effective_guides;
  if (!normalised.usable || !(fit.effective_guides >= params.min_effective_guides))
    return fit;  // fallback: no usable weights, or too few effective guides

  DVec3 resultant(0.0);
  for (size_t n = 0; n < count; ++n)
    resultant += weights[n] * glm::normalize(DVec3(directions.points[n]));
  fit.mean_resultant_length = glm::length(resultant);
  if (fit.mean_resultant_length > 0.0)
    fit.mean_direction = Vec3(resultant / fit.mean_resultant_length);
  const double kappa =
      params.concentration_scale * vmf_concentration_from_resultant(fit.mean_resultant_length);
  fit.concentration = std::clamp(kappa, params.min_concentration, params.max_concentration);
  fit.fallback = false;
  return fit;
}

Vec3 sample_vmf(const Vec3& mean, double concentration, Rng& rng) {
  const DVec3 axis = glm::normalize(DVec3(mean));
  const double u = 1.0 - rng.uniform_double();  // (0, 1]
  const double azimuth = kTwoPiDouble * rng.uniform_double();
  double one_minus_cos;
  if (concentration < kUniformConcentration) {
    one_minus_cos = 2.0 * u;  // uniform cosine on [-1, 1]
  } else {
    // 1 - cos = -log(u + (1 - u) e^{-2 kappa}) / kappa, computed without forming cos (which
    // would lose the small angles of a concentrated lobe).
    const double floor_term = std::exp(-2.0 * concentration);
    one_minus_cos = -std::log(u + (1.0 - u) * floor_term) / concentration;
  }
  one_minus_cos = std::clamp(one_minus_cos, 0.0, 2.0);
  const double cosine = 1.0 - one_minus_cos;
  const double sine = std::sqrt(one_minus_cos * (2.0 - one_minus_cos));
  const Frame frame{Vec3(axis)};
  DVec3 s(frame.s);
  s = glm::normalize(s - glm::dot(s, axis) * axis);
  const DVec3 t = glm::cross(axis, s);
  const DVec3 direction = cosine * axis + sine * (std::cos(azimuth) * s + std::sin(azimuth) * t);
  return Vec3(glm::normalize(direction));
}

double vmf_log_pdf(double concentration, double cos_to_mean) {
  if (concentration < kUniformConcentration) return -std::log(4.0 * kPiDouble);
  // The normaliser depends on kappa alone, and the anisotropic path perturbation's fallback
  // evaluates one kappa all render long: its three logs and expm1 were half of a fallback
  // density (docs/experiments.md, "Cost per mutation"). Kept for the last kappa,
  // per thread; the same value bit for bit.
  thread_local double last_concentration = std::numeric_limits<double>::quiet_NaN();
  thread_local double last_log_normaliser = 0.0;
  if (!(concentration == last_concentration)) {
    last_log_normaliser = std::log(concentration) - std::log(kTwoPiDouble) -
                          std::log(-std::expm1(-2.0 * concentration));
    last_concentration = concentration;
  }
  return last_log_normaliser + concentration * (cos_to_mean - 1.0);
}

DensityParts vmf_pdf_parts(double concentration, double cos_to_mean) {
  if (concentration < kUniformConcentration) return {1.0 / (4.0 * kPiDouble), 0.0};
  // kappa / (2 pi (1 - e^(-2 kappa))), kept for the last kappa as above.
  thread_local double last_concentration = std::numeric_limits<double>::quiet_NaN();
  thread_local double last_normaliser = 0.0;
  if (!(concentration == last_concentration)) {
    last_normaliser = concentration / (kTwoPiDouble * -std::expm1(-2.0 * concentration));
    last_concentration = concentration;
  }
  return {last_normaliser, concentration * (cos_to_mean - 1.0)};
}

namespace {

double cosine_between(const Vec3& a, const Vec3& b) {
  return std::clamp(glm::dot(glm::normalize(DVec3(a)), glm::normalize(DVec3(b))), -1.0, 1.0);
}

}  // namespace

DirectionalProposal propose_directional(const Vec3& current, const GuideSet& directions,
                                        const DirectionalParams& params, Rng& rng) {
  DirectionalProposal proposal;
  const VmfFit forward = fit_vmf(current, directions, params);
  proposal.direction = sample_vmf(current, forward.concentration, rng);
  proposal.forward_fallback = forward.fallback;
  const double cosine = cosine_between(current, proposal.direction);  // same both ways
  proposal.log_forward_density = vmf_log_pdf(forward.concentration, cosine);
  const VmfFit reverse = fit_vmf(proposal.direction, directions, params);
  proposal.reverse_fallback = reverse.fallback;
  proposal.log_reverse_density = vmf_log_pdf(reverse.concentration, cosine);
  return proposal;
}

double directional_log_density(const Vec3& from, const Vec3& to, const GuideSet& directions,
                               const DirectionalParams& params) {
  return vmf_log_pdf(fit_vmf(from, directions, params).concentration, cosine_between(from, to));
}

}  // namespace emlt::ensemble
