#include "mutations/multichain_perturbation.h"

#include "mutations/perturbation_common.h"

namespace emlt {

// Acceptance ratio. The move keeps x_0 .. x_l and the lens point; its variables are the
// image point u and, at each interior non-specular vertex z_j (l+1 < j < k), the outgoing
// direction ω_j. Together they map one-to-one (lobes fixed) onto z = (x_{l+1} .. x_{k-1}).
// Walking from the eye with u uniform on the film and each ω_j of solid-angle density 1
// would give z the ν-density (perturbation_common.h: log_eye_jacobian)
//     J(z) = Π_{i=l+1}^{k-1} pdf_from_eye(z_i) / d(z_{i+1}),
// d = the camera's 1 (its raster density stays in: it is the raster Jacobian), a Dirac
// vertex's lobe probability, or an interior vertex's directional density (there the factor
// is cos(z_i)/|z_i - z_{i+1}|², the pure solid-angle-to-area conversion). Hence
//     T(x -> y) = p_Δ(|u_y - u_x|) W H Π_j p_ω(θ_j) · J(y),
// with θ_j the angle between x's and y's outgoing directions at the j-th interior vertex,
// the same angle read from either path; p_Δ and p_ω depend on |Δ| and θ only, with fixed
// ranges, so they cancel in T(y->x)/T(x->y) provided both moves' angles lie in the range
// (checked on the measured angles, which both directions share). What remains is
//     log T(y->x)/T(x->y) = log J(x) - log J(y)
// plus the refraction-convention correction for x's Dirac values (radiance convention).
int MultiChainPerturbation::fixed_vertex(const PathType& type) {
  const int k = type.edges();
  int i = k - 1;
  int chains = 0;
  while (true) {
    while (i >= 1 && type.is_specular(i)) --i;
    if (i < 1) return -1;  // a chain ending at x_0: (L) S+ D ..., not this form
    ++chains;              // x_i is non-specular
    if (!type.is_specular(i - 1)) return chains >= 2 ? i - 1 : -1;
    --i;
  }
}

bool MultiChainPerturbation::walks_to_light(const Path& x) {
  const int k = x.edges();
  if (k < 2 || x.type.edges() != k) return false;
  const PathVertex& light = x.vertices.front();
  if (!light.is_surface() || !light.is_emitter() || !x.type.is_specular(1)) return false;
  // No two adjacent non-specular vertices between the lens and the light: every chain the
  // eye walk enters ends at the next non-specular vertex, the last one at the light.
  for (int i = k - 1; i >= 2; --i)
    if (!x.type.is_specular(i) && !x.type.is_specular(i - 1)) return false;
  return true;
}

int MultiChainPerturbation::walk_end(const Path& x) const {
  if (x.vertices.size() >= 5) {
    const int l = fixed_vertex(x.type);
    if (l >= 0) return l;
  }
  return walks_to_light_ && walks_to_light(x) ? -1 : kNotApplicable;
}

bool MultiChainPerturbation::applies_to(const Path& x, const MutationContext&) const {
  return walk_end(x) != kNotApplicable;
}

std::optional<Proposal> MultiChainPerturbation::retrace(const Path& x, const Vec2& raster,
                                                        const std::vector<Vec3>& directions,
                                                        const MutationContext& ctx) const {
  const int l = walk_end(x);
  if (l == kNotApplicable) return std::nullopt;
  size_t next_direction = 0;
  const auto interior_direction = [&](int, const Vec3&) -> std::optional<Vec3> {
    if (next_direction >= directions.size()) return std::nullopt;
    return directions[next_direction++];
  };
  Proposal proposal;
  Path& y = proposal.path;
  if (!perturbation::rebuild_eye_side(ctx.scene, x, l, raster, interior_direction, y)) return std::nullopt;
  proposal.log_reverse_over_forward = perturbation::eye_side_log_ratio(x, y, l, include_jacobian_);
  if (!std::isfinite(proposal.log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

std::optional<Proposal> MultiChainPerturbation::perturb_to(const Path& x, const Vec2& raster,
                                                           const std::vector<Vec3>& directions,
                                                           const MutationContext& ctx) const {
  auto proposal = retrace(x, raster, directions, ctx);
  if (!proposal) return std::nullopt;
  // Both moves must have their angles inside the (fixed) range.
  const int l = walk_end(x);
  const auto& xv = x.vertices;
  const auto& yv = proposal->path.vertices;
  for (int i = l + 2; i <= x.edges() - 1; ++i) {
    if (xv[size_t(i)].delta) continue;
    const double theta = perturbation::angle_between(perturbation::precise_direction(xv[size_t(i)], xv[size_t(i - 1)]),
                                                     perturbation::precise_direction(yv[size_t(i)], yv[size_t(i - 1)]));
    if (!(theta > theta_min_ && theta < theta_max_)) return std::nullopt;
  }
  return proposal;
}

std::optional<Proposal> MultiChainPerturbation::propose(const Path& x, Rng& rng,
                                                        const MutationContext& ctx) const {
  const int l = walk_end(x);
  if (l == kNotApplicable) return std::nullopt;
  const Camera& camera = ctx.scene.camera();
  const float r_max = ctx.lens_max_radius > 0.0f
                          ? ctx.lens_max_radius
                          : std::sqrt(0.05f * float(camera.width()) * float(camera.height()) / kPi);
  const Vec2 offset = perturbation::sample_image_offset(ctx.lens_min_radius, r_max, rng.uniform2());
  // One angular step per interior non-specular vertex, drawn around x's own direction there
  // (the notes' choice: the old direction, applied at the vertex's new position).
  thread_local std::vector<Vec3> directions;  // reused: no allocation per step
  directions.clear();
  const auto& xv = x.vertices;
  for (int i = x.edges() - 1; i >= l + 2; --i)
    if (!xv[size_t(i)].delta)
      directions.push_back(perturbation::perturb_direction(direction_between(xv[size_t(i)], xv[size_t(i - 1)]),
                                                           theta_min_, theta_max_, rng.uniform2()));
  return perturb_to(x, x.raster() + offset, directions, ctx);
}

}  // namespace emlt
