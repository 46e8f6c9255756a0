#pragma once
// The guided transition kernels of Ensemble MLT (Bashford-Rogers, Santos, Marnerides,
// Debattista, ACM TOG 41(1), 2021, section 3.2) as standalone mathematics: each kernel
// proposes a new single-vertex (or single-direction) state from the current one and from
// guides taken from the complementary ensemble, and reports what Metropolis-Hastings needs:
//
//     log T(y -> x) - log T(x -> y)    ("log density ratio", reverse over forward)
//
// so that a = min(1, f(y)/f(x) * exp(log ratio) * [P(n|y)/P(n|x) if a guide was drawn with
// state-dependent probabilities, see similarity.h]). Densities are with respect to area
// (R^2 / tangent plane / surface) or solid angle (S^2). The paper's typos and ambiguities,
// and the corrections applied here, are noted in each section below and in
// docs/emlt-fidelity.md. Every ratio is verified by running the kernel alone as
// an MH chain on a known target (tests/statistical/ensemble_kernel_test.cpp).
//
// Numerics: the interface uses emlt's float vectors; all arithmetic is in double.
#include <cmath>
#include <optional>
#include <span>

#include "emlt/core/math.h"
#include "emlt/core/rng.h"
#include "mutations/ensemble/similarity.h"

namespace emlt::ensemble {

// ---------------------------------------------------------------------------------------
// Stretch factor lambda, shared by the linear (R^2) and the great-arc (S^2) kernels.

enum class StretchDistribution {
  InverseSqrt,        // Goodman-Weare: g(l) ~ 1/sqrt(l) on [1/a, a], a = 1 + alpha
  UniformReciprocal,  // uniform on [1/a, a], a = 1 + alpha (support closed under l -> 1/l)
  UniformSymmetric,   // uniform on [1 - alpha, 1 + alpha], alpha < 1 (the paper's example);
                      // its support is not closed under inversion, so some moves are
                      // irreversible and must be rejected (ratio 0)
};

struct StretchParams {
  double alpha = 0.5;
  StretchDistribution distribution = StretchDistribution::InverseSqrt;
};

double sample_stretch(const StretchParams& params, Rng& rng);
// log g(lambda); -inf outside the support.
double stretch_log_pdf(double lambda, const StretchParams& params);
// Whether lambda lies in g's support, up to a relative tolerance (for lambdas recovered
// from rounded end points).
bool stretch_in_support(double lambda, const StretchParams& params,
                        double relative_tolerance = 1e-6);

// ---------------------------------------------------------------------------------------
// Linear kernel in R^N (the paper uses N = 2: image plane / lens): x' = v + l (x - v).
// Reverse over forward density ratio: g(1/l) / g(l) * l^(N-2). For the Goodman-Weare g,
// g(1/l) = l g(l), so the ratio is l^(N-1) = l in 2-D; for a uniform g on [1/a, a] it is
// l^(N-2) = 1 in 2-D (derivation in linear_kernel.cpp).

struct LinearProposal {
  Vec2 state{0.0f};
  double lambda = 1.0;
  double log_density_ratio = 0.0;  // log T(y -> x) - log T(x -> y); -inf: reject
  bool valid = false;              // false: current == guide (no line), or reverse impossible
};

double linear_log_density_ratio(double lambda, const StretchParams& params, int dimension = 2);
// When the reverse move draws its stretch from another distribution than the forward one
// (EMLT's nearby Υ: α is that of y's guides, not x's), the ratios above, which take both
// from `forward`, gain log g_reverse(1/l) - log g_forward(1/l). The same term serves the
// linear and the great-arc kernels (both invert a stretch l by 1/l). 0 when the two agree;
// -inf when 1/l is outside the reverse distribution's support.
double stretch_reverse_correction(double lambda, const StretchParams& forward,
                                  const StretchParams& reverse);
LinearProposal propose_linear(const Vec2& current, const Vec2& guide, const StretchParams& params,
                              Rng& rng);
// Ratio of a move `from -> to` along the line through `guide`, recovering lambda from the
// distances; used to evaluate a move given only its end points (e.g. after a ray-cast).
double linear_log_density_ratio_between(const Vec2& from, const Vec2& to, const Vec2& guide,
                                        const StretchParams& params);

// ---------------------------------------------------------------------------------------
// Great-arc ("linear hemispherical") kernel on S^2. With the guide w2 and the current w1 at
// angle W = acos(w1.w2), the proposal is the point of the great circle through w2 and w1
// at angle l*W from w2, on w1's side: slerp(w1, w2; t = 1 - l) =
//     sin(l W)/sin W * w1 + sin((1 - l) W)/sin W * w2
// (the paper prints the dot product where the angle W belongs). Reverse over forward:
//     g(1/l)/g(l) * (1/l) * sin(l W) / sin W  ==  sin(l W) / sin W  for Goodman-Weare g,
// i.e. sqrt(1 - (w_new.w2)^2) / sqrt(1 - (w1.w2)^2): the INVERSE of the paper's eq. 10
// (derivation in hemispherical_kernel.cpp). Moves with l W >= pi (past the guide's
// antipode) are not invertible by the same map and are reported invalid (reject).

struct GreatArcProposal {
  Vec3 direction{0.0f, 0.0f, 1.0f};
  double lambda = 1.0;
  double angle_current = 0.0;   // W: angle between current and guide
  double angle_proposed = 0.0;  // l W: angle between proposal and guide
  double log_density_ratio = 0.0;
  bool valid = false;
};

// The point of the great arc at stretch `lambda` (unit vectors in, unit vector out).
std::optional<Vec3> great_arc_point(const Vec3& current, const Vec3& guide, double lambda);
double great_arc_log_density_ratio(double lambda, double angle_current, double angle_proposed,
                                   const StretchParams& params);
// The same ratio for a move `from -> to` given only its end points (lambda and the angles
// recovered from them; `to` must lie on the great circle through `from` and `guide`).
double great_arc_log_density_ratio_between(const Vec3& from, const Vec3& to, const Vec3& guide,
                                           const StretchParams& params);
GreatArcProposal propose_great_arc(const Vec3& current, const Vec3& guide,
                                   const StretchParams& params, Rng& rng);

// ---------------------------------------------------------------------------------------
// Guides of the kernels that fit a distribution to all M guides (anisotropic, directional):
// per-guide points (vertex positions / directions) and optional per-guide log weights that
// do not depend on the perturbed vertex (e.g. log S(x_{j+1}, v_{j+1}) of eq. 11 for an
// unmoved neighbour). Empty context = all zero. The context may be given instead as
// similarity products (`context`, the cheaper form), or both, which then multiply.
struct GuideSet {
  std::span<const Vec3> points;
  std::span<const double> log_context_weights;
  std::span<const SimilarityProduct> context = {};
  // S(centre, points[n]) when the caller has it already (it must be that value: the fit uses
  // it in place of computing it); empty: computed.
  std::span<const double> similarity_to_centre = {};
  // A context given as one row of similarities (weight n gets the factor context_row[n]), in
  // place of `context` and `log_context_weights`, which must then be empty: the weights are
  // then formed without SimilarityProducts where they can be (normalise_row_products).
  std::span<const double> context_row = {};
  // The points as three coordinate arrays (guide n at (point_x[n], point_y[n], point_z[n]),
  // GuideView::coordinates' layout), in place of `points`, which must then be empty: the
  // anisotropic kernel reads them without a copy.
  std::span<const double> point_x = {}, point_y = {}, point_z = {};

  size_t size() const { return points.empty() ? point_x.size() : points.size(); }
  Vec3 point(size_t n) const {
    return points.empty() ? Vec3(float(point_x[n]), float(point_y[n]), float(point_z[n]))
                          : points[n];
  }
};

// The normalised weights of eq. 11, w(n) proportional to S(point, points[n]) * context(n)
// (without the S factor when `similarity` is null), as normalise_weights reports them.
NormalisedWeights guide_weights(const Vec3& point, const GuideSet& guides,
                                const SimilarityParams* similarity, std::span<double> weights);

// ---------------------------------------------------------------------------------------
// Anisotropic kernel (eqs. 11-12). At a vertex x with normal N: weights w(n) proportional
// to S(x, v^n) * context(n) (eq. 11), guides projected orthogonally onto the tangent plane
// at x, weighted 2x2 covariance (reliability weights, the analogue of the paper's
// 1/(M-1)), scaled, plus an isotropic floor; recentred at x. When the fit is degenerate
// (Kish effective number of guides below a threshold, or the raw covariance's determinant
// below a threshold) the kernel falls back. The ray-cast form (a vertex reached by a ray
// from the previous vertex through the sample) falls back as the paper does, to a
// concentrated vMF about the direction from that previous vertex to x; the planar form,
// which has no such vertex, to an isotropic Gaussian of fixed width. The decision is a
// deterministic function of (x, N, guides), so the reverse evaluation at x' makes it again
// for x'.

struct AnisotropicParams {
  SimilarityParams similarity;
  bool weight_by_similarity = true;  // false: w(n) ~ context(n) alone
  double covariance_scale = 1.0;     // multiplies the fitted covariance
  double floor_sigma = 1e-3;         // + floor_sigma^2 * I (keeps Sigma positive definite)
  double fallback_sigma = 0.05;      // width of the isotropic fallback Gaussian
  // > 0: the ray-cast form's fallback is a vMF of this concentration about the direction
  // from the cast origin to x (the paper's "von Mises-Fisher distribution aligned in the
  // direction x'_{j-1} -> x_j with a high concentration"). 0: the isotropic Gaussian, the
  // only fallback the planar form can use.
  double fallback_concentration = 0.0;
  double min_effective_guides = 2.0;  // Kish effective count below this -> fallback
  double min_determinant = 1e-12;     // det of the unfloored covariance below this -> fallback
  // Sigma as eq. 11 prints it: 1/(M-1) sum w(n) (u - mu)(u - mu)^T with normalised weights
  // (M guides), instead of the reliability-weighted covariance (see anisotropic_kernel.cpp).
  bool printed_normalisation = false;
  // < 1: the fitted Gaussian's scale mixture over s in [smallest_scale, 1], s log-uniform
  // (TangentGaussian::smallest_scale); 1: the Gaussian alone, as the paper has it.
  double smallest_scale = 1.0;
};

// A plane Gaussian's shape in its (s, t) coordinates, with what sampling and evaluating it use.
struct TangentCovariance {
  double ss = 1.0, st = 0.0, tt = 1.0;                       // the covariance
  double chol_ss = 1.0, chol_ts = 0.0, chol_tt = 1.0;        // its lower Cholesky factor
  double normaliser = 1.0 / (2.0 * 3.14159265358979323846);  // 1 / (2 pi sqrt(det))
};

// A Gaussian on the tangent plane of `centre`, mean at the centre.
struct TangentGaussian {
  DVec3 centre{0.0}, axis_s{1, 0, 0}, axis_t{0, 1, 0}, normal{0, 0, 1};
  TangentCovariance covariance;
  double effective_guides = 0.0;
  bool fallback = true;
  double fallback_concentration = 0.0;  // copied from the parameters when falling back
  // < 1: a step is s z with z ~ N(0, Sigma) and log s uniform on [log smallest_scale, 0]: the
  // Gaussian's shape at every scale from smallest_scale to 1, as Veach's lens perturbation
  // spreads its radii over two decades. The density has a closed form
  // (tangent_gaussian_pdf_parts). Fallback kernels stay single Gaussians.
  double smallest_scale = 1.0;
  bool scale_mixture() const { return smallest_scale < 1.0; }
  // The ray-cast form samples and evaluates a vMF about origin -> centre instead.
  bool directional_fallback() const { return fallback && fallback_concentration > 0.0; }
};

TangentGaussian fit_tangent_gaussian(const Vec3& centre, const Vec3& normal, const GuideSet& guides,
                                     const AnisotropicParams& params);
// A sample z' on the plane.
Vec3 sample_tangent_gaussian(const TangentGaussian& gaussian, Rng& rng);
// log density per unit plane area at a point of the plane (its normal component is ignored).
double tangent_gaussian_log_pdf(const TangentGaussian& gaussian, const Vec3& point_on_plane);

// A density as factor * exp(exponent): a move that multiplies several densities takes one
// log of the ratio of the products instead of one log a density and a fit (measured:
// docs/experiments.md, "Cost per mutation").
// factor 0 is a zero density.
struct DensityParts {
  double factor = 1.0, exponent = 0.0;
  DensityParts& operator*=(const DensityParts& other) {
    factor *= other.factor;
    exponent += other.exponent;
    return *this;
  }
  double log() const { return std::log(factor) + exponent; }
  bool positive_and_finite() const {
    return factor > 0.0 && std::isfinite(factor) && std::isfinite(exponent);
  }
};
// log(numerator / denominator) with one log.
inline double log_ratio(const DensityParts& numerator, const DensityParts& denominator) {
  return std::log(numerator.factor / denominator.factor) +
         (numerator.exponent - denominator.exponent);
}
DensityParts tangent_gaussian_pdf_parts(const TangentGaussian& gaussian,
                                        const Vec3& point_on_plane);

// General surfaces. The real strategy casts a ray from the previous vertex `origin` through
// z' and takes the first hit x' (normal N'). Per unit area of the surface, the density is
//     N(z') * |dA_plane / dA_surface| = N(z') * G(x' <-> origin) / G(z' <-> origin)
// with G = |cos at the receiving point| / distance^2 (the cosine at `origin` cancels).
double log_plane_to_surface_jacobian(double cos_at_surface, double distance_to_surface,
                                     double cos_at_plane, double distance_to_plane);
// The point where the line from `origin` through `through` meets the plane, if it does in
// front of the origin.
std::optional<Vec3> project_through_onto_plane(const Vec3& origin, const Vec3& through,
                                               const Vec3& plane_point, const Vec3& plane_normal);
// The point the ray from `origin` is cast through: a sample z' of the plane Gaussian, or,
// for a directional fallback, the point as far from the origin as the centre along a vMF
// direction about origin -> centre.
Vec3 sample_cast_target(const TangentGaussian& kernel, const Vec3& origin, Rng& rng);
// log area density of reaching `surface_point` (normal `surface_normal`) by sampling
// `gaussian` and casting from `origin`: finds z by central projection of surface_point
// onto the Gaussian's plane, then log N(z) + log Jacobian; for a directional fallback,
// log vMF(direction origin -> surface_point) + log G(surface_point <-> origin) with the
// cosine at the origin left out, as above. Use it for both directions:
//   forward: fit at x_j,  origin x'_{j-1}, surface point x'_j
//   reverse: fit at x'_j, origin x_{j-1},  surface point x_j
// (the reverse z is the central, not the orthogonal, projection of x_j: see the .cpp).
// Rays within min_plane_cosine of parallel to the plane get zero density (see the .cpp):
// the forward move refuses them, the reverse reports them impossible.
inline constexpr double kMinPlaneCosine = 1e-3;
double ray_cast_log_area_density(const TangentGaussian& gaussian, const Vec3& origin,
                                 const Vec3& surface_point, const Vec3& surface_normal,
                                 double min_plane_cosine = kMinPlaneCosine);
// The same density as parts (ray_cast_log_area_density is its log()).
DensityParts ray_cast_area_density_parts(const TangentGaussian& gaussian, const Vec3& origin,
                                         const Vec3& surface_point, const Vec3& surface_normal,
                                         double min_plane_cosine = kMinPlaneCosine);

// Standalone planar version: the surface is the tangent plane itself, so the ray-cast is
// the identity and the Jacobian is 1.
struct AnisotropicProposal {
  Vec3 state{0.0f};
  double log_forward_density = 0.0;  // log T(x -> y) per unit area
  double log_reverse_density = 0.0;  // log T(y -> x) per unit area, Sigma refitted at y
  bool forward_fallback = false;
  bool reverse_fallback = false;
  double log_density_ratio() const { return log_reverse_density - log_forward_density; }
};

AnisotropicProposal propose_anisotropic_on_plane(const Vec3& current, const Vec3& normal,
                                                 const GuideSet& guides,
                                                 const AnisotropicParams& params, Rng& rng);
// log T(from -> to) for the planar kernel (fit at `from`).
double anisotropic_on_plane_log_density(const Vec3& from, const Vec3& normal, const Vec3& to,
                                        const GuideSet& guides, const AnisotropicParams& params);

// ---------------------------------------------------------------------------------------
// Directional kernel on S^2: a von Mises-Fisher distribution fitted to the weighted guide
// directions (mean direction and the concentration from the mean resultant length), then
// recentred on the current direction: the proposal is vMF(current, kappa(current)). The
// reverse refits at the proposed direction: kappa(proposed).

struct DirectionalParams {
  SimilarityParams similarity;
  bool weight_by_direction_similarity = true;  // w(n) ~ S(w, w_n) * context(n)
  double concentration_scale = 1.0;            // multiplies the fitted kappa
  double min_concentration = 1e-3;
  double max_concentration = 1e6;
  double fallback_concentration = 100.0;  // "a high concentration" (paper, fallback)
  double min_effective_guides = 2.0;
};

struct VmfFit {
  Vec3 mean_direction{0.0f, 0.0f, 1.0f};  // of the weighted guides (not used by the kernel)
  double mean_resultant_length = 0.0;
  double concentration = 1.0;  // the kappa the kernel uses (scaled, clamped or fallback)
  double effective_guides = 0.0;
  bool fallback = true;
};

VmfFit fit_vmf(const Vec3& current, const GuideSet& directions, const DirectionalParams& params);
// Banerjee et al. (2005) estimate of kappa on S^2 from the mean resultant length.
double vmf_concentration_from_resultant(double mean_resultant_length);
Vec3 sample_vmf(const Vec3& mean, double concentration, Rng& rng);
// log density per unit solid angle at a direction whose cosine to the mean is cos_to_mean.
double vmf_log_pdf(double concentration, double cos_to_mean);
// The same density as parts: factor the normaliser, exponent kappa (cos - 1).
DensityParts vmf_pdf_parts(double concentration, double cos_to_mean);

struct DirectionalProposal {
  Vec3 direction{0.0f, 0.0f, 1.0f};
  double log_forward_density = 0.0;
  double log_reverse_density = 0.0;
  bool forward_fallback = false;
  bool reverse_fallback = false;
  double log_density_ratio() const { return log_reverse_density - log_forward_density; }
};

DirectionalProposal propose_directional(const Vec3& current, const GuideSet& directions,
                                        const DirectionalParams& params, Rng& rng);
double directional_log_density(const Vec3& from, const Vec3& to, const GuideSet& directions,
                               const DirectionalParams& params);

}  // namespace emlt::ensemble
