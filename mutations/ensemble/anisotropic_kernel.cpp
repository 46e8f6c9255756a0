// Anisotropic transition kernel of Ensemble MLT (section 3.2, eqs. 11-12).
//
// Fit. At the vertex x with normal N, each guide vertex v^n gets the weight of eq. 11,
// w(n) = S(x, v^n) * context(n) / sum_k (...), where context(n) carries the similarity of
// other, unperturbed vertices (eq. 11 multiplies in S(x_{j+1}, v^n_{j+1})). The guides are
// projected orthogonally onto the tangent plane at x and expressed in 2-D tangent
// coordinates. The paper prints mu = (1/M) sum w(n) v and Sigma = 1/(M-1) sum w(n) (v - mu)^2;
// with normalised weights the mean is sum w(n) v (the 1/M would shrink it), and Sigma must
// be the 2x2 outer-product covariance (a scalar square would be isotropic). We use the
// weighted covariance with reliability weights, sum w (u - mu)(u - mu)^T / (1 - sum w^2),
// which reduces to the paper's 1/(M-1) normalisation for equal weights; then
// Sigma = scale * Sigma_fit + floor^2 I. Read literally, with normalised weights, the printed
// Sigma is sum w (u - mu)(u - mu)^T / (M - 1): about 1/M of the weighted covariance, which
// printed_normalisation gives (then with scale 1). The Gaussian is recentred at x (mean = x), so
// only Sigma matters, and Sigma depends on x through the weights and the tangent plane.
//
// Fallback. If the Kish effective number of guides (sum w)^2 / sum w^2 is below
// min_effective_guides, or det(Sigma_fit) < min_determinant, the fit is not used. The
// ray-cast form then does what the paper does: it samples a direction from a vMF of
// concentration fallback_concentration about the direction from the cast origin x'_{j-1} to
// x_j and casts along it; per unit surface area that is vMF(w) |cos_x'| / d^2_x'. With no
// concentration set (and always in the planar form, which has no origin) the fallback is an
// isotropic Gaussian of width fallback_sigma on the tangent plane, the alternative the
// paper names. One guide typically dominates the similarity weights, so the fallback is
// common (about a third of the fits on the Cornell box). The decision is a function of
// (x, N, guides) only, so the reverse density at x' re-decides at x' - a kernel whose
// fallback decision was copied from the forward move would not be the same kernel in both
// directions (the statistical test shows that bias).
//
// Ratio (eq. 12). Forward: z' ~ N(x, Sigma(x)) on the plane at x, then the ray from x_{j-1}
// through z' hits the surface at x'. The change of variables from plane area to surface
// area goes through the solid angle at x_{j-1}: dA_plane = d^2_z / cos_z dw and
// dA_surface = d^2_x' / cos_x' dw, so per unit surface area
//     K(x -> x') = N(z' | x, Sigma(x)) * (cos_x' / d^2_x') / (cos_z' / d^2_z')
//                = N(z') G(x' <-> x_{j-1}) / G(z' <-> x_{j-1}),
// the paper's expression. Reverse: refit Sigma(x') on the plane at x', and find the z that
// the reverse move must have sampled to land on x. The paper says "x_j is projected onto
// the plane defined by x'_j and N(x'_j)"; since the reverse move reaches x by a ray from the
// previous vertex through z, z is the *central* projection of x from that vertex onto the
// plane (the intersection of the line x_{j-1} -> x_j with the plane), not the orthogonal
// projection. Then K(x' -> x) = N(z | x', Sigma(x')) G(x <-> x_{j-1}) / G(z <-> x_{j-1}).
// In a sequential path perturbation the forward move casts from the already-moved x'_{j-1}
// and the reverse from x_{j-1}; ray_cast_log_area_density takes the origin explicitly.
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

#include "emlt/core/frame.h"
#include "mutations/ensemble/guide_lanes.h"
#include "mutations/ensemble/kernels.h"

namespace emlt::ensemble {

namespace {

constexpr double kTwoPiDouble = 6.28318530717958647692;

// Orthonormal tangent basis in double precision from emlt's Frame (re-orthonormalised:
// the float basis is orthonormal only to ~1e-7).
void tangent_basis(const DVec3& normal, DVec3& axis_s, DVec3& axis_t) {
  const Frame frame{Vec3(normal)};
  DVec3 s(frame.s);
  s = glm::normalize(s - glm::dot(s, normal) * normal);
  axis_s = s;
  axis_t = glm::cross(normal, s);
}

TangentCovariance make_covariance(double ss, double st, double tt) {
  TangentCovariance c;
  c.ss = ss;
  c.st = st;
  c.tt = tt;
  c.chol_ss = std::sqrt(ss);
  c.chol_ts = st / c.chol_ss;
  c.chol_tt = std::sqrt(std::max(tt - c.chol_ts * c.chol_ts, 0.0));
  // N(0 | 0, Sigma) = 1 / (2 pi sqrt(det Sigma)), det = (chol_ss chol_tt)^2; its log is
  // taken only with the density's (DensityParts).
  c.normaliser = 1.0 / (kTwoPiDouble * (c.chol_ss * c.chol_tt));
  return c;
}

// make_covariance(variance, 0, variance) for the fallback kernel, whose variance is a
// parameter: kept for the last variance, per thread (a third of the fits fall back). The
// same values bit for bit.
const TangentCovariance& fallback_covariance(double variance) {
  thread_local double last_variance = std::numeric_limits<double>::quiet_NaN();
  thread_local TangentCovariance last;
  if (!(variance == last_variance)) {
    last = make_covariance(variance, 0.0, variance);
    last_variance = variance;
  }
  return last;
}

}  // namespace

NormalisedWeights guide_weights(const Vec3& point, const GuideSet& guides,
                                const SimilarityParams* similarity, std::span<double> weights) {
  const size_t count = guides.size();
  assert(weights.size() == count);
  if (!guides.context_row.empty()) {
    assert(guides.context.empty() && guides.log_context_weights.empty());
    if (!similarity) return normalise_row_products(guides.context_row, {}, weights);
    if (!guides.similarity_to_centre.empty())
      return normalise_row_products(guides.context_row, guides.similarity_to_centre, weights);
    GuideBuffer<double> to_centre(count);
    for (size_t n = 0; n < count; ++n)
      to_centre[n] = vertex_similarity(point, guides.point(n), *similarity);
    return normalise_row_products(guides.context_row, to_centre.span(), weights);
  }
  // Products of similarities underflow: kept as SimilarityProducts, normalised as such.
  GuideBuffer<SimilarityProduct> products(count);
  for (size_t n = 0; n < count; ++n) {
    SimilarityProduct& product = products[n];
    product = guides.context.empty() ? SimilarityProduct{} : guides.context[n];
    if (!guides.log_context_weights.empty()) product.multiply_log(guides.log_context_weights[n]);
    if (similarity)
      product.multiply(guides.similarity_to_centre.empty()
                           ? vertex_similarity(point, guides.point(n), *similarity)
                           : guides.similarity_to_centre[n]);
  }
  return normalise_weights(std::span<const SimilarityProduct>(products.span()), weights);
}

namespace {

// weights[n] = first[n] * second[n]; whether every factor and product is >= bound (false
// where one is NaN). Two guides at a time: the scalar loop and its three tests were a tenth
// of a fit.
bool plain_products(std::span<const double> first, std::span<const double> second,
                    std::span<double> weights, double bound) {
  const size_t count = weights.size();
  const double *a = first.data(), *b = second.data();
  double* w = weights.data();
  Mask2 plain = {-1, -1};
  size_t n = 0;
  for (; n + 2 <= count; n += 2) {
    const Double2 x = load2(a + n), y = load2(b + n), product = x * y;
    store2(w + n, product);
    plain &= (x >= bound) & (y >= bound) & (product >= bound);
  }
  bool result = (plain[0] & plain[1]) != 0;
  if (n < count) {
    w[n] = a[n] * b[n];
    result &= a[n] >= bound && b[n] >= bound && w[n] >= bound;
  }
  return result;
}

// eq. 11's weights for a fit, unnormalised where that is exact: with the context given as a
// row, w(n) = context_row[n] * S(centre, guide n) as plain doubles when every factor and
// product is >= kRenormalise (as normalise_row_products decides); else the normalised weights
// of guide_weights. A scatter is the same for any scale of its weights, and normalising them
// (a division a guide and a sum) cost a fifth of a fit
// (docs/experiments.md, "Cost per mutation"). `usable` as
// guide_weights reports it.
bool fit_weights(const Vec3& centre, const GuideSet& guides, const SimilarityParams* similarity,
                 std::span<double> weights) {
  const bool rows =
      !guides.context_row.empty() && (!similarity || !guides.similarity_to_centre.empty());
  if (rows) {
    constexpr double kRenormalise = SimilarityProduct::kRenormalise;
    const std::span<const double> first = guides.context_row;
    if (!similarity) {
      std::copy(first.begin(), first.end(), weights.begin());
      if (all_at_least(first, kRenormalise)) return true;
    } else if (plain_products(first, guides.similarity_to_centre, weights, kRenormalise)) {
      return true;
    }
  }
  return guide_weights(centre, guides, similarity, weights).usable;
}

// The weighted moments of the guides projected onto the tangent plane: the total weight, the
// sum of squared weights, and the scatter about the weighted mean in (s, t). Two passes (the
// mean, then the scatter about it: no cancellation when the guides are far from the centre),
// two guides at a time. West's one-pass update, which this replaced, divided once a guide
// and could not vectorise; the two agree to rounding.
struct TangentScatter {
  double total = 0.0, sum_of_squares = 0.0;
  double ss = 0.0, st = 0.0, tt = 0.0;
};

double lane_sum(Double2 v) {
  return v[0] + v[1];
}

TangentScatter tangent_scatter(const TangentGaussian& plane, const double* x, const double* y,
                               const double* z, std::span<const double> weights) {
  const size_t count = weights.size();
  const double* w = weights.data();
  GuideBuffer<double> s_buffer(count + 1), t_buffer(count + 1);
  double* s = s_buffer.span().data();
  double* t = t_buffer.span().data();
  const DVec3 c = plane.centre, a = plane.axis_s, b = plane.axis_t;
  // Orthogonal projection onto the plane = dropping the normal component.
  size_t n = 0;
  Double2 total{0, 0}, squares{0, 0}, sum_s{0, 0}, sum_t{0, 0};
  for (; n + 2 <= count; n += 2) {
    const Double2 dx = load2(x + n) - c.x, dy = load2(y + n) - c.y, dz = load2(z + n) - c.z;
    const Double2 ps = dx * a.x + dy * a.y + dz * a.z, pt = dx * b.x + dy * b.y + dz * b.z;
    store2(s + n, ps);
    store2(t + n, pt);
    const Double2 wn = load2(w + n);
    total += wn;
    squares += wn * wn;
    sum_s += wn * ps;
    sum_t += wn * pt;
  }
  TangentScatter result;
  result.total = lane_sum(total);
  result.sum_of_squares = lane_sum(squares);
  double weighted_s = lane_sum(sum_s), weighted_t = lane_sum(sum_t);
  if (n < count) {
    const double dx = x[n] - c.x, dy = y[n] - c.y, dz = z[n] - c.z;
    s[n] = dx * a.x + dy * a.y + dz * a.z;
    t[n] = dx * b.x + dy * b.y + dz * b.z;
    result.total += w[n];
    result.sum_of_squares += w[n] * w[n];
    weighted_s += w[n] * s[n];
    weighted_t += w[n] * t[n];
  }
  const double mean_s = weighted_s / result.total, mean_t = weighted_t / result.total;
  Double2 ss{0, 0}, st{0, 0}, tt{0, 0};
  for (n = 0; n + 2 <= count; n += 2) {
    const Double2 wn = load2(w + n);
    const Double2 ds = load2(s + n) - mean_s, dt = load2(t + n) - mean_t;
    ss += wn * ds * ds;
    st += wn * ds * dt;
    tt += wn * dt * dt;
  }
  result.ss = lane_sum(ss);
  result.st = lane_sum(st);
  result.tt = lane_sum(tt);
  if (n < count) {
    const double ds = s[n] - mean_s, dt = t[n] - mean_t;
    result.ss += w[n] * ds * ds;
    result.st += w[n] * ds * dt;
    result.tt += w[n] * dt * dt;
  }
  return result;
}

}  // namespace

TangentGaussian fit_tangent_gaussian(const Vec3& centre, const Vec3& normal, const GuideSet& guides,
                                     const AnisotropicParams& params) {
  TangentGaussian gaussian;
  gaussian.centre = DVec3(centre);
  gaussian.normal = glm::normalize(DVec3(normal));
  tangent_basis(gaussian.normal, gaussian.axis_s, gaussian.axis_t);
  const double fallback_variance = params.fallback_sigma * params.fallback_sigma;
  const size_t count = guides.size();
  const auto fall_back = [&] {
    gaussian.covariance = fallback_covariance(fallback_variance);
    gaussian.fallback = true;
    gaussian.fallback_concentration = params.fallback_concentration;
  };
  if (count == 0) {
    fall_back();
    return gaussian;
  }

  GuideBuffer<double> weight_buffer(count);
  const std::span<double> weights = weight_buffer.span();
  // All weights zero (or unusable): the selection rule would fall back to uniform weights,
  // but a fit needs real weights - use the fallback kernel.
  const bool weights_vanish = !fit_weights(
      centre, guides, params.weight_by_similarity ? &params.similarity : nullptr, weights);

  TangentScatter scatter;
  if (guides.points.empty()) {
    scatter = tangent_scatter(gaussian, guides.point_x.data(), guides.point_y.data(),
                              guides.point_z.data(), weights);
  } else {
    GuideBuffer<double> x(count), y(count), z(count);
    for (size_t n = 0; n < count; ++n) {
      x[n] = guides.points[n].x;
      y[n] = guides.points[n].y;
      z[n] = guides.points[n].z;
    }
    scatter = tangent_scatter(gaussian, x.span().data(), y.span().data(), z.span().data(), weights);
  }
  // Kish's effective number of guides, (sum w)^2 / sum w^2, and the reliability-weight
  // normalisation total - sum w^2 / total (= (M-1)/M of the total for equal weights).
  gaussian.effective_guides = scatter.total * scatter.total / scatter.sum_of_squares;
  const double normaliser = params.printed_normalisation
                                ? double(count - 1) * scatter.total
                                : scatter.total - scatter.sum_of_squares / scatter.total;
  bool degenerate = weights_vanish || !(gaussian.effective_guides >= params.min_effective_guides) ||
                    !(normaliser > 0.0);
  double ss = 0.0, st = 0.0, tt = 0.0;
  if (!degenerate) {
    ss = scatter.ss / normaliser;
    st = scatter.st / normaliser;
    tt = scatter.tt / normaliser;
    const double determinant = ss * tt - st * st;
    degenerate = !(determinant >= params.min_determinant) || !std::isfinite(determinant);
  }
  if (degenerate) {
    fall_back();
    return gaussian;
  }
  const double floor_variance = params.floor_sigma * params.floor_sigma;
  const double scale = params.covariance_scale;
  gaussian.covariance =
      make_covariance(scale * ss + floor_variance, scale * st, scale * tt + floor_variance);
  gaussian.fallback = false;
  gaussian.smallest_scale = params.smallest_scale;
  return gaussian;
}

Vec3 sample_tangent_gaussian(const TangentGaussian& gaussian, Rng& rng) {
  // Box-Muller: two independent standard normals, then the Cholesky factor.
  const double radius = std::sqrt(-2.0 * std::log(1.0 - rng.uniform_double()));
  const double angle = kTwoPiDouble * rng.uniform_double();
  double n1 = radius * std::cos(angle), n2 = radius * std::sin(angle);
  if (gaussian.scale_mixture()) {
    const double scale = std::exp(rng.uniform_double() * std::log(gaussian.smallest_scale));
    n1 *= scale;
    n2 *= scale;
  }
  const double s = gaussian.covariance.chol_ss * n1;
  const double t = gaussian.covariance.chol_ts * n1 + gaussian.covariance.chol_tt * n2;
  return Vec3(gaussian.centre + s * gaussian.axis_s + t * gaussian.axis_t);
}

DensityParts tangent_gaussian_pdf_parts(const TangentGaussian& gaussian,
                                        const Vec3& point_on_plane) {
  const DVec3 offset = DVec3(point_on_plane) - gaussian.centre;
  const double s = glm::dot(offset, gaussian.axis_s), t = glm::dot(offset, gaussian.axis_t);
  // Mahalanobis distance via the Cholesky factor: solve L y = (s, t), then |y|^2.
  const double y1 = s / gaussian.covariance.chol_ss;
  const double y2 = (t - gaussian.covariance.chol_ts * y1) / gaussian.covariance.chol_tt;
  const double m2 = y1 * y1 + y2 * y2;  // squared Mahalanobis distance
  if (!gaussian.scale_mixture()) return {gaussian.covariance.normaliser, -0.5 * m2};
  // The scale mixture: with a = smallest_scale and log s uniform on [log a, 0],
  //   integral over s of N(d | 0, s^2 Sigma) ds / (s ln(1/a))
  //     = (exp(-m2 / 2) - exp(-m2 / (2 a^2))) / (2 pi sqrt(det Sigma) ln(1/a) m2)
  // (substitute u = 1 / s^2). As factor * exp(-m2 / 2), the factor's bracket through expm1
  // keeps the limit (1 / a^2 - 1) / (2 ln(1/a)) at m2 = 0.
  const double a2 = gaussian.smallest_scale * gaussian.smallest_scale;
  const double log_inverse = -std::log(gaussian.smallest_scale);
  const double spread = 0.5 * (1.0 / a2 - 1.0);
  const double bracket = m2 > 0.0 ? -std::expm1(-m2 * spread) / m2 : spread;
  return {gaussian.covariance.normaliser * bracket / log_inverse, -0.5 * m2};
}

double tangent_gaussian_log_pdf(const TangentGaussian& gaussian, const Vec3& point_on_plane) {
  return tangent_gaussian_pdf_parts(gaussian, point_on_plane).log();
}

double log_plane_to_surface_jacobian(double cos_at_surface, double distance_to_surface,
                                     double cos_at_plane, double distance_to_plane) {
  // log[(|cos_x'| / d_x'^2) / (|cos_z'| / d_z'^2)], one log of the ratio: four logs were a
  // third of a density evaluation (docs/experiments.md, "Cost per mutation").
  // The cosines are at least kMinPlaneCosine or
  // nonzero, the distances scene lengths: the ratio neither overflows nor underflows.
  return std::log((std::abs(cos_at_surface) * (distance_to_plane * distance_to_plane)) /
                  (std::abs(cos_at_plane) * (distance_to_surface * distance_to_surface)));
}

std::optional<Vec3> project_through_onto_plane(const Vec3& origin, const Vec3& through,
                                               const Vec3& plane_point, const Vec3& plane_normal) {
  const DVec3 start(origin), direction = DVec3(through) - DVec3(origin);
  const DVec3 normal(plane_normal);
  const double denominator = glm::dot(direction, normal);
  if (std::abs(denominator) <= 1e-12 * glm::length(direction) * glm::length(normal))
    return std::nullopt;
  const double distance = glm::dot(DVec3(plane_point) - start, normal) / denominator;
  if (!(distance > 0.0)) return std::nullopt;  // the plane is behind the origin
  return Vec3(start + distance * direction);
}

Vec3 sample_cast_target(const TangentGaussian& kernel, const Vec3& origin, Rng& rng) {
  if (!kernel.directional_fallback()) return sample_tangent_gaussian(kernel, rng);
  const DVec3 axis = kernel.centre - DVec3(origin);
  const double length = glm::length(axis);
  if (!(length > 0.0)) return origin;  // no direction: the cast fails
  // A point as far out as the centre: the caller's float subtraction of the origin then
  // keeps the direction to float precision relative to that distance, not to |origin|.
  const DVec3 direction(sample_vmf(Vec3(axis), kernel.fallback_concentration, rng));
  return Vec3(DVec3(origin) + length * direction);
}

namespace {

// The directional fallback's density per unit area at surface_point.
DensityParts vmf_cast_area_density_parts(const TangentGaussian& kernel, const Vec3& origin,
                                         const Vec3& surface_point, const Vec3& surface_normal) {
  const DVec3 start(origin), axis = kernel.centre - start,
                             to_surface = DVec3(surface_point) - start;
  const double axis_length = glm::length(axis), distance = glm::length(to_surface);
  if (!(axis_length > 0.0) || !(distance > 0.0)) return {0.0, 0.0};
  const DVec3 direction = to_surface / distance;
  const double cos_at_surface = glm::dot(direction, glm::normalize(DVec3(surface_normal)));
  if (cos_at_surface == 0.0) return {0.0, 0.0};
  // 1 - cos from the chord, which keeps the small angles of a concentrated lobe.
  const DVec3 chord = direction - axis / axis_length;
  const double cos_to_mean = 1.0 - 0.5 * glm::dot(chord, chord);
  DensityParts density = vmf_pdf_parts(kernel.fallback_concentration, cos_to_mean);
  density.factor *= std::abs(cos_at_surface) / (distance * distance);
  return density;
}

}  // namespace

DensityParts ray_cast_area_density_parts(const TangentGaussian& gaussian, const Vec3& origin,
                                         const Vec3& surface_point, const Vec3& surface_normal,
                                         double min_plane_cosine) {
  if (gaussian.directional_fallback())
    return vmf_cast_area_density_parts(gaussian, origin, surface_point, surface_normal);
  const auto plane_point = project_through_onto_plane(origin, surface_point, Vec3(gaussian.centre),
                                                      Vec3(gaussian.normal));
  if (!plane_point) return {0.0, 0.0};
  const DVec3 start(origin);
  const DVec3 to_surface = DVec3(surface_point) - start, to_plane = DVec3(*plane_point) - start;
  const double distance_to_surface = glm::length(to_surface),
               distance_to_plane = glm::length(to_plane);
  const DVec3 direction = to_surface / distance_to_surface;
  const double cos_at_surface = glm::dot(direction, glm::normalize(DVec3(surface_normal)));
  const double cos_at_plane = glm::dot(direction, gaussian.normal);
  // A ray nearly parallel to the plane: the origin lies (within rounding) on the plane, as
  // when a moved vertex lands on the face of the vertex the Gaussian is centred on. The plane
  // point then follows the hit only through rounding errors, so neither density can be
  // evaluated: the kernel never makes such moves, in either direction (zero density), which
  // keeps forward and reverse consistent. The statistical tests show the bias otherwise.
  if (cos_at_surface == 0.0 || std::abs(cos_at_plane) < min_plane_cosine) return {0.0, 0.0};
  DensityParts density = tangent_gaussian_pdf_parts(gaussian, *plane_point);
  // (|cos_x'| / d_x'^2) / (|cos_z'| / d_z'^2), the plane-to-surface Jacobian.
  density.factor *= (std::abs(cos_at_surface) * (distance_to_plane * distance_to_plane)) /
                    (std::abs(cos_at_plane) * (distance_to_surface * distance_to_surface));
  return density;
}

double ray_cast_log_area_density(const TangentGaussian& gaussian, const Vec3& origin,
                                 const Vec3& surface_point, const Vec3& surface_normal,
                                 double min_plane_cosine) {
  return ray_cast_area_density_parts(gaussian, origin, surface_point, surface_normal,
                                     min_plane_cosine)
      .log();
}

AnisotropicProposal propose_anisotropic_on_plane(const Vec3& current, const Vec3& normal,
                                                 const GuideSet& guides,
                                                 const AnisotropicParams& params, Rng& rng) {
  AnisotropicProposal proposal;
  const TangentGaussian forward = fit_tangent_gaussian(current, normal, guides, params);
  proposal.state = sample_tangent_gaussian(forward, rng);
  proposal.forward_fallback = forward.fallback;
  // Both densities at the stored (float) states, so that they describe the same pair.
  proposal.log_forward_density = tangent_gaussian_log_pdf(forward, proposal.state);
  const TangentGaussian reverse = fit_tangent_gaussian(proposal.state, normal, guides, params);
  proposal.reverse_fallback = reverse.fallback;
  proposal.log_reverse_density = tangent_gaussian_log_pdf(reverse, current);
  return proposal;
}

double anisotropic_on_plane_log_density(const Vec3& from, const Vec3& normal, const Vec3& to,
                                        const GuideSet& guides, const AnisotropicParams& params) {
  return tangent_gaussian_log_pdf(fit_tangent_gaussian(from, normal, guides, params), to);
}

}  // namespace emlt::ensemble
