#include "mutations/lens_perturbation.h"

#include "mutations/perturbation_common.h"

namespace emlt {

// Acceptance ratio. The path layer's f(x) is a density over the reference measure ν (area
// measure on every vertex, Dirac vertices as in vertex.h; see perturbation_common.h), and f
// includes the camera importance W_e and every G. The move keeps x_0 .. x_l and the lens
// point x_k and maps the image point u (pixels) one-to-one onto the moved vertices
// z = (x_{l+1} .. x_{k-1}), lobes fixed. If u were uniform on the film (density 1/(WH)), the walk through the chain would give z
// the ν-density  P_eye(z) / Π_{Dirac i} p_lobe(z_i),  P_eye = Π_{i=l+1}^{k-1} pdf_from_eye(z_i)
// (the camera's direction density and each Dirac vertex's lobe probability times its area
// conversion; dividing by the lobe probabilities because the perturbation does not choose
// lobes). Hence du = W H J(z) dν(z) with J = P_eye / Π p_lobe, and
//     T(x -> y) = p_Δ(u_y - u_x) · W H · J(y),      T(y -> x) = p_Δ(u_x - u_y) · W H · J(x).
// p_Δ depends on |Δ| only (1/r radius, uniform angle) and the lens point is the same, so
//     a = min(1, f(y) T(y->x) / (f(x) T(x->y))) = min(1, [f(y) / J(y)] / [f(x) / J(x)]),
// i.e. log T(y->x)/T(x->y) = log J(x) - log J(y). The camera term does not cancel by itself
// in this representation: f contains W_e G(x_{k-1}, x_k), and J contains the camera's
// direction density times cos/d² at x_{k-1}; their quotient is the constant 1/p_lens
// (camera.h's normalisation), which is Mitsuba's "W-only" form: f/J is the eye subpath's
// throughput with Dirac values in place of value/probability, times the connection and
// the fixed prefix. Nothing depends on r_min, r_max. One correction on top: refraction
// values of the path layer depend on which walk stored them (perturbation_common.h,
// log_convention_correction); y's are written in the radiance convention and x's are
// converted to it, so the two f are compared in one representation.
int LensPerturbation::fixed_vertex(const PathType& type) {
  const int k = type.edges();
  if (k < 2) return -1;
  int first_diffuse = k - 1;
  while (first_diffuse >= 1 && type.is_specular(first_diffuse)) --first_diffuse;
  if (first_diffuse < 1) return -1;  // L S* E: nothing to connect
  const int l = first_diffuse - 1;
  return type.is_specular(l) ? -1 : l;
}

bool LensPerturbation::applies_to(const Path& x, const MutationContext&) const {
  return x.vertices.size() >= 3 && fixed_vertex(x.type) >= 0;
}

std::optional<Proposal> LensPerturbation::perturb_to(const Path& x, const Vec2& raster,
                                                     const MutationContext& ctx) const {
  const int l = fixed_vertex(x.type);
  if (l < 0) return std::nullopt;
  Proposal proposal;
  if (!perturbation::rebuild_eye_side(ctx.scene, x, l, raster, nullptr, proposal.path))
    return std::nullopt;
  proposal.log_reverse_over_forward = perturbation::eye_side_log_ratio(x, proposal.path, l, include_jacobian_);
  if (!std::isfinite(proposal.log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

std::optional<Proposal> LensPerturbation::propose(const Path& x, Rng& rng,
                                                  const MutationContext& ctx) const {
  const Camera& camera = ctx.scene.camera();
  const float r_max = ctx.lens_max_radius > 0.0f
                          ? ctx.lens_max_radius
                          : std::sqrt(0.05f * float(camera.width()) * float(camera.height()) / kPi);
  const Vec2 offset = perturbation::sample_image_offset(ctx.lens_min_radius, r_max, rng.uniform2());
  return perturb_to(x, x.raster() + offset, ctx);
}

}  // namespace emlt
