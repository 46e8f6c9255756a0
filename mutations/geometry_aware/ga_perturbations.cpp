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

// The cone of a segment between `floor` and `saturation`: the angles below and above which
// the step range it limits is at its lower or upper clamp anyway, so that a narrower or
// wider cone changes nothing. The estimate is exact between its alpha_min and alpha_max
// (and returns alpha_min whenever the cone is narrower), so passing these gives the same
// ranges while the estimate stops early at the floor and keeps its point queries' balls
// small (cone.h: their size grows with tan α).
double cone(const MutationContext& ctx, const PathVertex& apex, const PathVertex& other,
            double floor, double saturation) {
  const double alpha_max = std::clamp(saturation * (1.0 + 1e-9), kAlphaMin, kAlphaMax);
  const double alpha_min = std::clamp(floor * (1.0 - 1e-9), kAlphaMin, alpha_max);
  using geometry_aware::ConeMethod;
  const ConeMethod method = ctx.field_cone                 ? ConeMethod::Field
                            : ctx.cone_cell_fraction > 0.0 ? ConeMethod::Cells
                                                           : ConeMethod::Exact;
  return geometry_aware::cone_half_angle(ctx.scene, apex, other, alpha_min, alpha_max, method,
                                         ctx.cone_cell_fraction);
}

double distance(const PathVertex& a, const PathVertex& b) {
  return glm::length(DVec3(a.position) - DVec3(b.position));
}

double default_max_radius(const MutationContext& ctx) {
  const Camera& camera = ctx.scene.camera();
  return ctx.lens_max_radius > 0.0f ? double(ctx.lens_max_radius)
                                    : std::sqrt(0.05 * camera.width() * camera.height() / M_PI);
}

// [lo, hi] for a range whose Veach bounds are [min, max]: hi = ceiling · max, lo the larger
// of 3 · min and floor · max (and never above hi).
void clamp_bounds(const GeometryAwareParams& p, double veach_min, double veach_max, double cap, double* lo,
                  double* hi) {
  *hi = std::min(p.ceiling * veach_max, cap);
  *lo = std::min(*hi, std::max(3.0 * veach_min, p.floor * veach_max));
}

// R(z) for an image-plane move that rebuilds z's vertices l+1 .. k-1 and connects x_l. An
// offset of ρ pixels moves x_{l+1} by about ρ·rpp·L_eye (L_eye the eye subpath's length,
// as in Veach's caustic heuristic), which turns the connection seen from the fixed x_l by
// that over |x_{l+1} − x_l|: it must stay within the connection's cone (apex x_l).
double image_radius_limit(const Path& z, int l, const MutationContext& ctx, const GeometryAwareParams& p) {
  const auto& v = z.vertices;
  const int k = z.edges();
  const double r1 = double(ctx.lens_min_radius);
  double lo = 0.0, hi = 0.0;
  clamp_bounds(p, r1, default_max_radius(ctx), std::numeric_limits<double>::infinity(), &lo, &hi);
  const Camera& camera = ctx.scene.camera();
  const double rpp = perturbation::radians_per_pixel(camera);
  // ρ ≥ hi / c saturates R at hi, ρ ≤ lo / c puts it at lo.
  const double rho_min = lo / p.step_scale;
  double rho = hi / p.step_scale;
  if (!v[size_t(l)].is_environment()) {
    // An orthographic film moves x_{l+1} by ρ pixels' width on the film, whatever the
    // distance (its rays are parallel).
    double eye_length = 0.0;
    if (!camera.is_orthographic())
      for (int j = l + 1; j <= k - 1; ++j) eye_length += distance(v[size_t(j + 1)], v[size_t(j)]);
    const double per_pixel =
        (camera.is_orthographic() ? camera.film_pixel_size() : rpp * eye_length) /
        distance(v[size_t(l + 1)], v[size_t(l)]);
    rho =
        cone(ctx, v[size_t(l)], v[size_t(l + 1)], rho_min * per_pixel, rho * per_pixel) / per_pixel;
  }
  // The eye connection of an orthographic camera does not turn as the image point moves
  // (it slides along the film): no cone limits it.
  if (p.eye_cone && rho > rho_min && !camera.is_orthographic())
    rho = std::min(rho, cone(ctx, v[size_t(k)], v[size_t(k - 1)], rho_min * rpp, rho * rpp) / rpp);
  return std::clamp(p.step_scale * rho, lo, hi);
}

// Whether an offset or angle lies in a range [.., limit]; the tolerance absorbs the float
// rounding of a sample drawn exactly at the limit (u = 0), the same in both directions.
bool within(double value, double limit) { return value <= limit * (1.0 + 1e-6); }

// log ln(b(x)/a) − log ln(b(y)/a): the normalisation ratio of two 1/t laws on [a, b].
double log_range_ratio(double a, double b_x, double b_y) {
  return std::log(std::log(b_x / a)) - std::log(std::log(b_y / a));
}

}  // namespace

void prepare_cones(const MutationContext& ctx) {
  ctx.scene.surface_bvh();
  if (ctx.field_cone) ctx.scene.clearance_field();
}

// ---------------------------------------------------------------------------------------
// Lens.

double GaLensPerturbation::max_radius(const Path& z, const MutationContext& ctx) const {
  return image_radius_limit(z, LensPerturbation::fixed_vertex(z.type), ctx, params_);
}

std::optional<Proposal> GaLensPerturbation::perturb_to(const Path& x, const Vec2& raster,
                                                       const MutationContext& ctx) const {
  const double offset = glm::length(glm::dvec2(raster) - glm::dvec2(x.raster()));
  const double r_x = max_radius(x, ctx);
  if (!within(offset, r_x)) return std::nullopt;  // not a move x could propose
  auto proposal = base_.perturb_to(x, raster, ctx);
  if (!proposal) return std::nullopt;
  if (params_.stage_one_keeps_x_range)
    proposal->log_reverse_over_forward += std::log(std::log(r_x / double(ctx.lens_min_radius)));
  if (ctx.may_defer) {
    proposal->deferred = true;
    return proposal;
  }
  proposal->log_reverse_over_forward = with_deferred(
      proposal->log_reverse_over_forward, reverse_range_term(x, r_x, proposal->path, ctx));
  return proposal;
}

double GaLensPerturbation::reverse_range_term(const Path& x, double r_x, const Path& y,
                                              const MutationContext& ctx) const {
  const double r1 = double(ctx.lens_min_radius);
  const double offset = glm::length(glm::dvec2(y.raster()) - glm::dvec2(x.raster()));
  const double r_y = params_.reverse_uses_x_cones ? r_x : max_radius(y, ctx);
  if (!within(offset, r_y)) return kNegativeInfinity;
  // Planar densities 1/(2π|Δ|² ln(R/r1)): the |Δ|² cancel, the normalisations do not.
  if (params_.stage_one_keeps_x_range) return -std::log(std::log(r_y / r1));
  return log_range_ratio(r1, r_x, r_y);
}

double GaLensPerturbation::deferred_log_ratio(const Path& x, const Proposal& proposal,
                                              const MutationContext& ctx) const {
  return reverse_range_term(x, max_radius(x, ctx), proposal.path, ctx);
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
  double veach_max = 0.0, lo = 0.0, hi = 0.0;
  CausticPerturbation::angle_range(z, l, ctx, theta_min, &veach_max);
  clamp_bounds(params_, *theta_min, veach_max, 0.5 * M_PI, &lo, &hi);
  // The turn at x_l must stay in the first segment's cone (apex x_l); it moves x_{k-1} by
  // about θ·L_chain, seen from the lens as θ·L_chain/d_eye, which must stay in the eye
  // connection's cone (apex at the lens).
  double chain_length = 0.0;
  for (int j = l; j <= k - 2; ++j) chain_length += distance(v[size_t(j + 1)], v[size_t(j)]);
  const double eye_per_theta = chain_length / distance(v[size_t(k - 1)], v[size_t(k)]);
  // limit ≥ hi / c saturates Θ at hi; the second cone only matters below the first.
  const double limit_min = lo / params_.step_scale;
  double limit = cone(ctx, v[size_t(l)], v[size_t(l + 1)], limit_min, hi / params_.step_scale);
  // (An orthographic camera's eye connection slides instead of turning: no second cone.)
  if (limit > limit_min && !ctx.scene.camera().is_orthographic())
    limit = std::min(limit, cone(ctx, v[size_t(k)], v[size_t(k - 1)], limit_min * eye_per_theta,
                                 limit * eye_per_theta) /
                                eye_per_theta);
  *theta_max = std::clamp(params_.step_scale * limit, lo, hi);
}

std::optional<Proposal> GaCausticPerturbation::perturb_to(const Path& x, const Vec3& direction,
                                                          const MutationContext& ctx) const {
  const int l = CausticPerturbation::fixed_vertex(x.type);
  if (l < 0) return std::nullopt;
  double min_x = 0.0, max_x = 0.0;
  angle_range(x, ctx, &min_x, &max_x);
  const DVec3 x_direction = perturbation::precise_direction(x.vertices[size_t(l)], x.vertices[size_t(l + 1)]);
  if (!within(perturbation::angle_between(x_direction, DVec3(direction)), max_x)) return std::nullopt;
  // The base move without its own (Veach-range) angular terms: ours replace them.
  auto proposal = base_.retrace(x, direction, ctx);
  if (!proposal) return std::nullopt;
  const double theta = turn_angle(x, proposal->path);
  if (!(theta > min_x && within(theta, max_x))) return std::nullopt;
  if (ctx.may_defer) {
    proposal->deferred = true;
    return proposal;
  }
  proposal->log_reverse_over_forward =
      with_deferred(proposal->log_reverse_over_forward,
                    reverse_range_term(min_x, max_x, theta, proposal->path, ctx));
  if (std::isnan(proposal->log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

double GaCausticPerturbation::turn_angle(const Path& x, const Path& y) const {
  const int l = CausticPerturbation::fixed_vertex(x.type);
  return perturbation::angle_between(
      perturbation::precise_direction(x.vertices[size_t(l)], x.vertices[size_t(l + 1)]),
      perturbation::precise_direction(y.vertices[size_t(l)], y.vertices[size_t(l + 1)]));
}

double GaCausticPerturbation::reverse_range_term(double min_x, double max_x, double theta,
                                                 const Path& y, const MutationContext& ctx) const {
  double min_y = min_x, max_y = max_x;
  if (!params_.reverse_uses_x_cones) angle_range(y, ctx, &min_y, &max_y);
  if (!(theta > min_y && within(theta, max_y))) return kNegativeInfinity;
  // Solid-angle densities 1/(2π θ sin θ ln(Θ/θ1)) with each path's own θ1 and Θ.
  return std::log(std::log(max_x / min_x)) - std::log(std::log(max_y / min_y));
}

double GaCausticPerturbation::deferred_log_ratio(const Path& x, const Proposal& proposal,
                                                 const MutationContext& ctx) const {
  double min_x = 0.0, max_x = 0.0;
  angle_range(x, ctx, &min_x, &max_x);
  const double term =
      reverse_range_term(min_x, max_x, turn_angle(x, proposal.path), proposal.path, ctx);
  return std::isnan(term) ? kNegativeInfinity : term;
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
  double lo = 0.0, hi = 0.0;
  clamp_bounds(params_, base_.theta_min(), base_.theta_max(), 0.5 * M_PI, &lo, &hi);
  std::vector<double> limits;
  for (int i = z.edges() - 1; i >= l + 2; --i)
    if (!v[size_t(i)].delta)
      limits.push_back(
          std::clamp(params_.step_scale * cone(ctx, v[size_t(i)], v[size_t(i - 1)],
                                               lo / params_.step_scale, hi / params_.step_scale),
                     lo, hi));
  return limits;
}

double GaMultiChainPerturbation::max_radius(const Path& z, const MutationContext& ctx) const {
  return image_radius_limit(z, MultiChainPerturbation::fixed_vertex(z.type), ctx, params_);
}

std::optional<Proposal> GaMultiChainPerturbation::perturb_to(const Path& x, const Vec2& raster,
                                                             const std::vector<Vec3>& directions,
                                                             const MutationContext& ctx) const {
  const int l = MultiChainPerturbation::fixed_vertex(x.type);
  if (l < 0) return std::nullopt;
  const double offset = glm::length(glm::dvec2(raster) - glm::dvec2(x.raster()));
  const double r_x = max_radius(x, ctx);
  if (!within(offset, r_x)) return std::nullopt;
  // The base move without its fixed-range check: the ranges are ours.
  auto proposal = base_.retrace(x, raster, directions, ctx);
  if (!proposal) return std::nullopt;
  const auto limits_x = angle_limits(x, ctx);
  const std::vector<double> thetas = turn_angles(x, proposal->path);
  for (size_t j = 0; j < thetas.size(); ++j)
    if (!(thetas[j] > base_.theta_min() * (1.0 - 1e-6) && within(thetas[j], limits_x[j])))
      return std::nullopt;
  if (ctx.may_defer) {
    // A first part that is not finite is a rejection whatever the ranges.
    if (!std::isfinite(proposal->log_reverse_over_forward)) return std::nullopt;
    proposal->deferred = true;
    return proposal;
  }
  const double term = reverse_range_term(x, r_x, limits_x, thetas, proposal->path, ctx);
  if (term == kNegativeInfinity) {
    proposal->log_reverse_over_forward = kNegativeInfinity;
    return proposal;
  }
  proposal->log_reverse_over_forward += term;
  if (!std::isfinite(proposal->log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

// The angles between x's and y's directions at the interior non-specular vertices, in the
// base's order (from the eye).
std::vector<double> GaMultiChainPerturbation::turn_angles(const Path& x, const Path& y) const {
  const int l = MultiChainPerturbation::fixed_vertex(x.type);
  std::vector<double> thetas;
  for (int i = x.edges() - 1; i >= l + 2; --i)
    if (!x.vertices[size_t(i)].delta)
      thetas.push_back(perturbation::angle_between(
          perturbation::precise_direction(x.vertices[size_t(i)], x.vertices[size_t(i - 1)]),
          perturbation::precise_direction(y.vertices[size_t(i)], y.vertices[size_t(i - 1)])));
  return thetas;
}

double GaMultiChainPerturbation::reverse_range_term(const Path& x, double r_x,
                                                    const std::vector<double>& limits_x,
                                                    const std::vector<double>& thetas,
                                                    const Path& y,
                                                    const MutationContext& ctx) const {
  const double r1 = double(ctx.lens_min_radius), theta1 = base_.theta_min();
  const double offset = glm::length(glm::dvec2(y.raster()) - glm::dvec2(x.raster()));
  const double r_y = params_.reverse_uses_x_cones ? r_x : max_radius(y, ctx);
  const auto limits_y = params_.reverse_uses_x_cones ? limits_x : angle_limits(y, ctx);
  bool reverse_possible = within(offset, r_y);
  double term = log_range_ratio(r1, r_x, r_y);
  // θ1 is the same in both directions.
  for (size_t j = 0; j < thetas.size(); ++j) {
    if (!within(thetas[j], limits_y[j])) reverse_possible = false;
    term += log_range_ratio(theta1, limits_x[j], limits_y[j]);
  }
  return reverse_possible ? term : kNegativeInfinity;
}

double GaMultiChainPerturbation::deferred_log_ratio(const Path& x, const Proposal& proposal,
                                                    const MutationContext& ctx) const {
  const double term = reverse_range_term(x, max_radius(x, ctx), angle_limits(x, ctx),
                                         turn_angles(x, proposal.path), proposal.path, ctx);
  // A ratio that is not finite rejects the move, as perturb_to does without deferral.
  return std::isfinite(term) ? term : kNegativeInfinity;
}

std::optional<Proposal> GaMultiChainPerturbation::propose(const Path& x, Rng& rng, const MutationContext& ctx) const {
  const int l = MultiChainPerturbation::fixed_vertex(x.type);
  if (l < 0) return std::nullopt;
  const double r_x = max_radius(x, ctx);
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
