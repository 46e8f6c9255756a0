#include "mutations/geometry_aware/ga_perturbations.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mutations/geometry_aware/cone.h"
#include "mutations/perturbation_common.h"

namespace emlt {

namespace {

constexpr double kNegativeInfinity = -std::numeric_limits<double>::infinity();
// Cone limits: below 1e-6 rad every step range is at its floor anyway; π/2 is a half-space.
constexpr double kAlphaMin = 1e-6, kAlphaMax = 0.5 * M_PI;

// The cone of a segment, up to `saturation`: the angle beyond which the step range it
// limits is at its upper clamp anyway, so that a wider cone changes nothing. The estimate
// is exact up to its alpha_max, so passing the saturation angle gives the same ranges and
// keeps the point queries' balls small (cone.h: their size grows with tan α).
double cone(const Scene& scene, const PathVertex& apex, const PathVertex& other, double saturation = kAlphaMax) {
  const double alpha_max = std::clamp(saturation * (1.0 + 1e-9), kAlphaMin, kAlphaMax);
  return geometry_aware::cone_half_angle(scene, apex, other, kAlphaMin, alpha_max);
}

double distance(const PathVertex& a, const PathVertex& b) {
  return glm::length(DVec3(a.position) - DVec3(b.position));
}

double default_max_radius(const MutationContext& ctx) {
  const Camera& camera = ctx.scene.camera();
  return ctx.lens_max_radius > 0.0f ? double(ctx.lens_max_radius)
                                    : std::sqrt(0.05 * camera.width() * camera.height() / M_PI);
}

// R(z) for an image-plane move that rebuilds z's vertices l+1 .. k-1 and connects x_l. An
// offset of ρ pixels turns the eye ray by ρ·rpp, which must stay within the eye segment's
// cone (apex at the lens), and moves x_{l+1} by about ρ·rpp·L_eye (L_eye the eye subpath's
// length, as in Veach's caustic heuristic), which turns the connection seen from the fixed
// x_l by that over |x_{l+1} − x_l|, to stay within the connection's cone (apex x_l).
double image_radius_limit(const Path& z, int l, const MutationContext& ctx, double step_scale) {
  const auto& v = z.vertices;
  const int k = z.edges();
  const double r1 = double(ctx.lens_min_radius), r2 = default_max_radius(ctx);
  const double rpp = perturbation::radians_per_pixel(ctx.scene.camera());
  // ρ ≥ r2 / c saturates R at r2.
  const double rho_max = r2 / step_scale;
  double rho = cone(ctx.scene, v[size_t(k)], v[size_t(k - 1)], rho_max * rpp) / rpp;
  if (!v[size_t(l)].is_environment()) {
    double eye_length = 0.0;
    for (int j = l + 1; j <= k - 1; ++j) eye_length += distance(v[size_t(j + 1)], v[size_t(j)]);
    const double connection_length = distance(v[size_t(l + 1)], v[size_t(l)]);
    const double alpha_connection =
        cone(ctx.scene, v[size_t(l)], v[size_t(l + 1)], rho_max * rpp * eye_length / connection_length);
    rho = std::min(rho, alpha_connection * connection_length / (rpp * eye_length));
  }
  return std::clamp(step_scale * rho, std::min(r2, 3.0 * r1), r2);
}

// Whether an offset or angle lies in a range [.., limit]; the tolerance absorbs the float
// rounding of a sample drawn exactly at the limit (u = 0), the same in both directions.
bool within(double value, double limit) { return value <= limit * (1.0 + 1e-6); }

// log ln(b(x)/a) − log ln(b(y)/a): the normalisation ratio of two 1/t laws on [a, b].
double log_range_ratio(double a, double b_x, double b_y) {
  return std::log(std::log(b_x / a)) - std::log(std::log(b_y / a));
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Lens.

double GaLensPerturbation::max_radius(const Path& z, const MutationContext& ctx) const {
  return image_radius_limit(z, LensPerturbation::fixed_vertex(z.type), ctx, params_.step_scale);
}

std::optional<Proposal> GaLensPerturbation::perturb_to(const Path& x, const Vec2& raster,
                                                       const MutationContext& ctx) const {
  auto proposal = base_.perturb_to(x, raster, ctx);
  if (!proposal) return std::nullopt;
  const double r1 = double(ctx.lens_min_radius);
  const double offset = glm::length(glm::dvec2(raster) - glm::dvec2(x.raster()));
  const double r_x = max_radius(x, ctx);
  if (!within(offset, r_x)) return std::nullopt;  // not a move x could propose
  const double r_y = params_.reverse_uses_x_cones ? r_x : max_radius(proposal->path, ctx);
  if (!within(offset, r_y)) {
    proposal->log_reverse_over_forward = kNegativeInfinity;
    return proposal;
  }
  // Planar densities 1/(2π|Δ|² ln(R/r1)): the |Δ|² cancel, the normalisations do not.
  proposal->log_reverse_over_forward += log_range_ratio(r1, r_x, r_y);
  return proposal;
}

std::optional<Proposal> GaLensPerturbation::propose(const Path& x, Rng& rng, const MutationContext& ctx) const {
  if (LensPerturbation::fixed_vertex(x.type) < 0) return std::nullopt;
  const double r_x = max_radius(x, ctx);
  const Vec2 offset = perturbation::sample_image_offset(ctx.lens_min_radius, float(r_x), rng.uniform2());
  return perturb_to(x, x.raster() + offset, ctx);
}

// ---------------------------------------------------------------------------------------
// Caustic.

void GaCausticPerturbation::angle_range(const Path& z, const MutationContext& ctx, double* theta_min,
                                        double* theta_max) const {
  const int l = CausticPerturbation::fixed_vertex(z.type);
  const auto& v = z.vertices;
  const int k = z.edges();
  double veach_max = 0.0;
  CausticPerturbation::angle_range(z, l, ctx, theta_min, &veach_max);
  // The turn at x_l must stay in the first segment's cone (apex x_l); it moves x_{k-1} by
  // about θ·L_chain, seen from the lens as θ·L_chain/d_eye, which must stay in the eye
  // segment's cone (apex at the lens).
  double chain_length = 0.0;
  for (int j = l; j <= k - 2; ++j) chain_length += distance(v[size_t(j + 1)], v[size_t(j)]);
  const double eye_distance = distance(v[size_t(k - 1)], v[size_t(k)]);
  // limit ≥ veach_max / c saturates Θ at veach_max.
  const double limit_max = veach_max / params_.step_scale;
  const double limit =
      std::min(cone(ctx.scene, v[size_t(l)], v[size_t(l + 1)], limit_max),
               cone(ctx.scene, v[size_t(k)], v[size_t(k - 1)], limit_max * chain_length / eye_distance) *
                   eye_distance / chain_length);
  *theta_max = std::clamp(params_.step_scale * limit, std::min(veach_max, 3.0 * *theta_min), veach_max);
}

std::optional<Proposal> GaCausticPerturbation::perturb_to(const Path& x, const Vec3& direction,
                                                          const MutationContext& ctx) const {
  auto proposal = base_.perturb_to(x, direction, ctx);
  if (!proposal) return std::nullopt;
  const Path& y = proposal->path;
  const int l = CausticPerturbation::fixed_vertex(x.type);
  const double theta = perturbation::angle_between(perturbation::precise_direction(x.vertices[size_t(l)], x.vertices[size_t(l + 1)]),
                                                   perturbation::precise_direction(y.vertices[size_t(l)], y.vertices[size_t(l + 1)]));
  double min_x = 0.0, max_x = 0.0, min_y = 0.0, max_y = 0.0;
  angle_range(x, ctx, &min_x, &max_x);
  if (!(theta > min_x && within(theta, max_x))) return std::nullopt;
  // Veach's range holds ours, so the base's −∞ (θ outside y's Veach range) stands.
  if (!std::isfinite(proposal->log_reverse_over_forward)) return proposal;
  double veach_min_x = 0.0, veach_max_x = 0.0, veach_min_y = 0.0, veach_max_y = 0.0;
  CausticPerturbation::angle_range(x, l, ctx, &veach_min_x, &veach_max_x);
  CausticPerturbation::angle_range(y, l, ctx, &veach_min_y, &veach_max_y);
  const double veach_term =
      std::log(std::log(veach_max_x / veach_min_x)) - std::log(std::log(veach_max_y / veach_min_y));
  if (params_.reverse_uses_x_cones) {
    min_y = min_x, max_y = max_x;
  } else {
    angle_range(y, ctx, &min_y, &max_y);
  }
  if (!(theta > min_y && within(theta, max_y))) {
    proposal->log_reverse_over_forward = kNegativeInfinity;
    return proposal;
  }
  // Solid-angle densities 1/(2π θ sin θ ln(Θ/θ1)) with each path's own θ1 and Θ.
  const double ga_term = std::log(std::log(max_x / min_x)) - std::log(std::log(max_y / min_y));
  proposal->log_reverse_over_forward += ga_term - veach_term;
  if (std::isnan(proposal->log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

std::optional<Proposal> GaCausticPerturbation::propose(const Path& x, Rng& rng, const MutationContext& ctx) const {
  const int l = CausticPerturbation::fixed_vertex(x.type);
  if (l < 0) return std::nullopt;
  double theta_min = 0.0, theta_max = 0.0;
  angle_range(x, ctx, &theta_min, &theta_max);
  if (!(theta_max > theta_min) || !(theta_min > 0.0)) return std::nullopt;
  const Vec3 old_direction = direction_between(x.vertices[size_t(l)], x.vertices[size_t(l + 1)]);
  return perturb_to(x, perturbation::perturb_direction(old_direction, theta_min, theta_max, rng.uniform2()), ctx);
}

// ---------------------------------------------------------------------------------------
// Multi-chain.

std::vector<double> GaMultiChainPerturbation::angle_limits(const Path& z, const MutationContext& ctx) const {
  const int l = MultiChainPerturbation::fixed_vertex(z.type);
  const auto& v = z.vertices;
  const double floor = std::min(base_.theta_max(), 3.0 * base_.theta_min());
  std::vector<double> limits;
  for (int i = z.edges() - 1; i >= l + 2; --i)
    if (!v[size_t(i)].delta)
      limits.push_back(std::clamp(
          params_.step_scale * cone(ctx.scene, v[size_t(i)], v[size_t(i - 1)], base_.theta_max() / params_.step_scale),
          floor, base_.theta_max()));
  return limits;
}

std::optional<Proposal> GaMultiChainPerturbation::perturb_to(const Path& x, const Vec2& raster,
                                                             const std::vector<Vec3>& directions,
                                                             const MutationContext& ctx) const {
  auto proposal = base_.perturb_to(x, raster, directions, ctx);
  if (!proposal) return std::nullopt;
  const Path& y = proposal->path;
  const int l = MultiChainPerturbation::fixed_vertex(x.type);
  const double r1 = double(ctx.lens_min_radius);
  const double offset = glm::length(glm::dvec2(raster) - glm::dvec2(x.raster()));
  const double r_x = image_radius_limit(x, l, ctx, params_.step_scale);
  const auto limits_x = angle_limits(x, ctx);
  const double r_y = params_.reverse_uses_x_cones ? r_x : image_radius_limit(y, l, ctx, params_.step_scale);
  const auto limits_y = params_.reverse_uses_x_cones ? limits_x : angle_limits(y, ctx);
  if (!within(offset, r_x)) return std::nullopt;
  bool reverse_possible = within(offset, r_y);
  double term = log_range_ratio(r1, r_x, r_y);
  // The angles in the base's order (from the eye); the base checked θ_j ∈ (θ1, θ2).
  size_t j = 0;
  for (int i = x.edges() - 1; i >= l + 2; --i) {
    if (x.vertices[size_t(i)].delta) continue;
    const double theta = perturbation::angle_between(
        perturbation::precise_direction(x.vertices[size_t(i)], x.vertices[size_t(i - 1)]),
        perturbation::precise_direction(y.vertices[size_t(i)], y.vertices[size_t(i - 1)]));
    if (!within(theta, limits_x[j])) return std::nullopt;
    if (!within(theta, limits_y[j])) reverse_possible = false;
    term += log_range_ratio(base_.theta_min(), limits_x[j], limits_y[j]);
    ++j;
  }
  if (!reverse_possible) {
    proposal->log_reverse_over_forward = kNegativeInfinity;
    return proposal;
  }
  proposal->log_reverse_over_forward += term;
  if (!std::isfinite(proposal->log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

std::optional<Proposal> GaMultiChainPerturbation::propose(const Path& x, Rng& rng, const MutationContext& ctx) const {
  const int l = MultiChainPerturbation::fixed_vertex(x.type);
  if (l < 0) return std::nullopt;
  const double r_x = image_radius_limit(x, l, ctx, params_.step_scale);
  const Vec2 offset = perturbation::sample_image_offset(ctx.lens_min_radius, float(r_x), rng.uniform2());
  const auto limits = angle_limits(x, ctx);
  std::vector<Vec3> directions;
  size_t j = 0;
  const auto& xv = x.vertices;
  for (int i = x.edges() - 1; i >= l + 2; --i)
    if (!xv[size_t(i)].delta)
      directions.push_back(perturbation::perturb_direction(direction_between(xv[size_t(i)], xv[size_t(i - 1)]),
                                                           base_.theta_min(), limits[j++], rng.uniform2()));
  return perturb_to(x, x.raster() + offset, directions, ctx);
}

}  // namespace emlt
