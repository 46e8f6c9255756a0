#pragma once
// The density jump (density_jump.h) on the image point of Veach's lens-perturbation paths
// ((L|D) D S* E eye ends; `--mutations ...,emlt-jump=W`): the new image point is drawn from
// the kernel density estimate over the image points of Υ (the frozen ensemble's paths of
// the same type), the ray from the same lens point is retraced through the same specular
// lobes and connected to the fixed x_l, exactly as the lens perturbation does. So
//   log T(y->x)/T(x->y) = [log J(x) - log J(y)]   (LensPerturbation::perturb_to)
//                       + log q(u_x) - log q(u_y).
// Unlike the paper's linear lens kernel it needs no similarity weights of the moved vertices
// (the guide is drawn uniformly), so a step costs a lens perturbation plus 2M exponentials.
// `emlt-jump-near` weighs the guides by the similarity (eq. 8) of their vertex l to the fixed
// x_l instead: guides whose light side passes near ours land where a connection to x_l is
// likely to exist. x_l is kept by the move, so the weights are the same in reverse and no
// selection ratio enters (one similarity row of M entries a step). With fewer than
// two guides of x's type the step is Veach's lens perturbation (the type is kept, so the
// reverse step sees the same Υ and makes the same decision).
#include "emlt/mcmc/mutation.h"
#include "mutations/lens_perturbation.h"

namespace emlt {

class DensityJumpLens final : public Mutation {
 public:
  // drop_density_ratio = true leaves log q(u_x) - log q(u_y) out (a deliberately wrong
  // strategy, for the test that shows the term matters).
  explicit DensityJumpLens(bool near_fixed_vertex = false, bool drop_density_ratio = false)
      : near_fixed_vertex_(near_fixed_vertex), drop_density_ratio_(drop_density_ratio) {}
  std::string_view name() const override {
    return near_fixed_vertex_ ? "emlt-jump-near" : "emlt-jump";
  }
  bool applies_to(const Path& x, const MutationContext& ctx) const override {
    return veach_.applies_to(x, ctx);
  }
  std::optional<Proposal> propose(const Path& x, Rng& rng,
                                  const MutationContext& ctx) const override;

 private:
  LensPerturbation veach_;
  bool near_fixed_vertex_;
  bool drop_density_ratio_;
};

}  // namespace emlt
