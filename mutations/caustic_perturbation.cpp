#include "mutations/caustic_perturbation.h"

#include "mutations/perturbation_common.h"

namespace emlt {

// Acceptance ratio. The move keeps x_0 .. x_l and the lens point x_k; the free variable is
// the unit direction ω leaving x_l, which maps one-to-one (lobes fixed) onto the moved
// vertices z = (x_{l+1} .. x_{k-1}). A walk from x_l sampling ω with solid-angle density 1
// would give z the ν-density (perturbation_common.h)
//     K(z) = cos(z_{l+1})/|z_{l+1} - x_l|²  ·  Π_{i=l+2}^{k-1} pdf_from_light(z_i) /
//     p_lobe(z_{i-1}),
// the area conversions and refraction factors of each Dirac step without its lobe choice.
// So dω = K(z) dν(z), and with the angular density
//     p_ω(θ | x) = 1 / (2π ln(θ_2(x)/θ_1(x)) θ sin θ)   for θ_1(x) < θ < θ_2(x), else 0,
// θ being the angle between x's and y's directions at x_l (the same from either side),
//     T(x -> y) = p_ω(θ | x) K(y),    T(y -> x) = p_ω(θ | y) K(x),
//     log T(y->x)/T(x->y) = log K(x) - log K(y) + log ln(θ_2/θ_1)(x) - log ln(θ_2/θ_1)(y),
// and -∞ when θ lies outside y's range (the reverse move could not happen). The heuristic
// scales θ_1 and θ_2 by the same path-dependent factor, so the ln terms cancel unless the
// π/2 cap changed one of them. f(y) brings the new W_e, G and raster at the lens and the new
// BSDF value at x_l; the Dirac values are written in the importance convention and x's are
// converted to it (log_convention_correction) so both f use one representation.
int CausticPerturbation::fixed_vertex(const PathType& type) {
  const int k = type.edges();
  if (k < 2 || type.is_specular(k - 1)) return -1;
  int l = k - 2;
  while (l >= 1 && type.is_specular(l)) --l;
  return l;  // x_0 (L) or a non-specular vertex
}

bool CausticPerturbation::applies_to(const Path& x, const MutationContext&) const {
  if (x.vertices.size() < 3) return false;
  const int l = fixed_vertex(x.type);
  // A sky vertex is a direction itself: there is no fixed point to turn a direction at.
  return l >= 0 && !x.vertices[size_t(l)].is_environment();
}

void CausticPerturbation::angle_range(const Path& z, int l, const MutationContext& ctx,
                                      double* theta_min, double* theta_max) {
  const auto& v = z.vertices;
  const int k = z.edges();
  const Camera& camera = ctx.scene.camera();
  const double r_max = ctx.lens_max_radius > 0.0f
                           ? double(ctx.lens_max_radius)
                           : std::sqrt(0.05 * camera.width() * camera.height() / M_PI);
  double chain_length = 0.0;
  for (int j = l; j <= k - 2; ++j)
    chain_length += glm::length(DVec3(v[size_t(j + 1)].position) - DVec3(v[size_t(j)].position));
  const double eye_distance =
      glm::length(DVec3(v[size_t(k - 1)].position) - DVec3(v[size_t(k)].position));
  // The angle at x_l that moves x_{k-1} by about one pixel's footprint there: a pixel's
  // angle times the eye distance, or an orthographic film's pixel itself.
  const double scale = camera.is_orthographic()
                           ? camera.film_pixel_size() / chain_length
                           : perturbation::radians_per_pixel(camera) * eye_distance / chain_length;
  *theta_min = double(ctx.lens_min_radius) * scale;
  *theta_max = std::min(r_max * scale, 0.5 * M_PI);
}

std::optional<Proposal> CausticPerturbation::retrace(const Path& x, const Vec3& direction,
                                                     const MutationContext& ctx) const {
  const Scene& scene = ctx.scene;
  const int l = fixed_vertex(x.type);
  const int k = x.edges();
  if (l < 0) return std::nullopt;
  const auto& xv = x.vertices;
  Proposal proposal;
  Path& y = proposal.path;
  y = x;
  auto& yv = y.vertices;

  // Trace from x_l and through the chain with the same lobes, in importance mode.
  const PathVertex& fixed = xv[size_t(l)];
  if (fixed.is_environment()) return std::nullopt;
  Ray ray = spawn_ray(fixed.position, fixed.normal, direction);
  for (int i = l + 1; i <= k - 1; ++i) {
    auto hit = perturbation::trace_surface(scene, ray);
    if (!hit) return std::nullopt;
    hit->throughput = xv[size_t(i)].throughput;
    yv[size_t(i)] = *hit;
    if (i == k - 1) break;
    const bool transmission =
        perturbation::crosses_surface(xv[size_t(i)], xv[size_t(i + 1)], xv[size_t(i - 1)]);
    const auto next = perturbation::continue_through_delta(
        yv[size_t(i)], direction_between(yv[size_t(i)], yv[size_t(i - 1)]),
        TransportMode::Importance, transmission);
    if (!next) return std::nullopt;
    ray = spawn_ray(yv[size_t(i)].position, yv[size_t(i)].normal, *next);
  }
  for (int i = l + 1; i <= k - 2; ++i) {
    const bool transmission =
        perturbation::crosses_surface(xv[size_t(i)], xv[size_t(i + 1)], xv[size_t(i - 1)]);
    if (!perturbation::fill_delta_record(yv[size_t(i)], yv[size_t(i + 1)], yv[size_t(i - 1)],
                                         TransportMode::Importance, transmission))
      return std::nullopt;
  }

  // The new non-specular vertex seen from the fixed lens point: the pixel moves (an
  // orthographic film point moves with it, to its projection: camera.h).
  PathVertex& lens = yv.back();
  if (!perturbation::aim_lens_at(scene, lens, yv[size_t(k - 1)])) return std::nullopt;
  const Rgb connection =
      connect_vertices(scene, &yv[size_t(k - 2)], yv[size_t(k - 1)], lens, nullptr);
  if (is_black(connection) || !is_finite(connection)) return std::nullopt;
  if (!perturbation::finish_proposal(scene, x, y, l + 1, k - 1)) return std::nullopt;

  const double log_jacobians = include_jacobian_
                                   ? perturbation::log_light_jacobian(x, l + 1, k - 1) -
                                         perturbation::log_light_jacobian(y, l + 1, k - 1)
                                   : 0.0;
  const double convention =
      perturbation::log_convention_correction(x, l + 1, k - 2, TransportMode::Importance);
  proposal.log_reverse_over_forward = log_jacobians - convention;
  if (std::isnan(proposal.log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

std::optional<Proposal> CausticPerturbation::perturb_to(const Path& x, const Vec3& direction,
                                                        const MutationContext& ctx) const {
  const int l = fixed_vertex(x.type);
  if (l < 0) return std::nullopt;
  double min_x = 0.0, max_x = 0.0;
  angle_range(x, l, ctx, &min_x, &max_x);
  return perturb_within(x, direction, ctx, min_x, max_x);
}

std::optional<Proposal> CausticPerturbation::perturb_within(const Path& x, const Vec3& direction,
                                                            const MutationContext& ctx,
                                                            double min_x, double max_x) const {
  auto proposal = retrace(x, direction, ctx);
  if (!proposal) return std::nullopt;
  const int l = fixed_vertex(x.type);
  const auto& xv = x.vertices;
  const auto& yv = proposal->path.vertices;
  // Angle between the two directions at x_l, and both moves' ranges.
  const double theta = perturbation::angle_between(
      perturbation::precise_direction(xv[size_t(l)], xv[size_t(l + 1)]),
      perturbation::precise_direction(yv[size_t(l)], yv[size_t(l + 1)]));
  if (!(theta > min_x && theta < max_x) || !(max_x > min_x)) return std::nullopt;
  double min_y = 0.0, max_y = 0.0;
  angle_range(proposal->path, l, ctx, &min_y, &max_y);
  if (!(theta > min_y && theta < max_y) || !(max_y > min_y)) {
    proposal->log_reverse_over_forward = -std::numeric_limits<double>::infinity();
    return proposal;
  }
  // Both ranges are the same image-plane radii scaled by each path's pixel angle, so their
  // ratio θ_2/θ_1 is the same unless θ_2 was clamped at π/2: the term is then exactly zero,
  // and skipping it saves four logarithms a step (about 1 % of an MLT render's time).
  const double ratio_x = max_x / min_x, ratio_y = max_y / min_y;
  if (std::abs(ratio_x - ratio_y) > 1e-12 * ratio_x)
    proposal->log_reverse_over_forward += std::log(std::log(ratio_x) / std::log(ratio_y));
  if (std::isnan(proposal->log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

std::optional<Proposal> CausticPerturbation::propose(const Path& x, Rng& rng,
                                                     const MutationContext& ctx) const {
  const int l = fixed_vertex(x.type);
  if (l < 0) return std::nullopt;
  double theta_min = 0.0, theta_max = 0.0;
  angle_range(x, l, ctx, &theta_min, &theta_max);
  if (!(theta_max > theta_min) || !(theta_min > 0.0)) return std::nullopt;
  const Vec3 old_direction = direction_between(x.vertices[size_t(l)], x.vertices[size_t(l + 1)]);
  return perturb_within(
      x, perturbation::perturb_direction(old_direction, theta_min, theta_max, rng.uniform2()), ctx,
      theta_min, theta_max);
}

}  // namespace emlt
