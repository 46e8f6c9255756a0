#pragma once
// Veach's caustic perturbation (1997 §11.4.3) for paths whose
// eye end is (L|D) S* D E: the direction leaving the fixed light-side vertex x_l is turned
// by a 1/θ-distributed angle, traced through the same specular lobes to a new non-specular
// vertex x_{k-1}, which is connected to the fixed lens point (so the pixel moves). The lens
// perturbation cannot move caustics (its eye ray would have to hit the specular chain's end
// exactly); this moves them from the light side.
//
// Angle range: Veach's length-scaled heuristic (thesis p. 354, as in Mitsuba):
//   θ_i = r_i · (radians per pixel) · |x_{k-1} - x_k| / Σ_{j=l}^{k-2} |x_{j+1} - x_j|,
// r_1 = ctx.lens_min_radius, r_2 = ctx.lens_max_radius, so that x_{k-1} moves about r_1..r_2
// pixels as seen from the eye. θ_2 is capped at π/2.
#include "emlt/mcmc/mutation.h"

namespace emlt {

class CausticPerturbation final : public Mutation {
 public:
  // include_jacobian = false drops the area-measure Jacobian (tests only).
  explicit CausticPerturbation(bool include_jacobian = true) : include_jacobian_(include_jacobian) {}

  std::string_view name() const override { return "caustic"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override;
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;

  // The deterministic part: x with the direction leaving x_l replaced by `direction`.
  std::optional<Proposal> perturb_to(const Path& x, const Vec3& direction, const MutationContext& ctx) const;
  // The same without the angular step's terms: the ratio holds only the Jacobians and the
  // convention correction, for a caller whose direction density is its own (EMLT's guided
  // caustic perturbation adds its great-arc kernel's ratio).
  std::optional<Proposal> retrace(const Path& x, const Vec3& direction, const MutationContext& ctx) const;

  // Index l of the fixed vertex of a (L|D) S* D E suffix, or -1.
  static int fixed_vertex(const PathType& type);
  // The heuristic's angle range for path z with fixed vertex l.
  static void angle_range(const Path& z, int l, const MutationContext& ctx, double* theta_min,
                          double* theta_max);

 private:
  // perturb_to with x's angle range already known (propose has just computed it).
  std::optional<Proposal> perturb_within(const Path& x, const Vec3& direction, const MutationContext& ctx,
                                         double min_x, double max_x) const;

  bool include_jacobian_;
};

}  // namespace emlt
