#pragma once
// EMLT's linear lens perturbation (Bashford-Rogers et al. 2021, §3.3): on the paths of
// Veach's lens perturbation ((L|D) D S* E eye ends), the image point moves along the line
// through a guide path's image point, x' = v + λ (x - v) (the linear kernel, kernels.h),
// with the guide v^n drawn from Υ in proportion to the similarity of the eye subpath
// (camera to first non-specular vertex, eq. 9). The rest is Veach's deterministic retrace.
//
// T(x -> y) = P(n | x) K_lin(u_x -> u_y) W H J(y), so
//   log T(y->x)/T(x->y) = [log J(x) - log J(y)]  (LensPerturbation::perturb_to)
//                       + log K_lin ratio        (λ for the Goodman-Weare g)
//                       + log P(n|y) - log P(n|x).
// With fewer than two guides of x's type the step is Veach's lens perturbation; since the
// move keeps the type, the reverse step sees the same Υ and makes the same choice.
#include "mutations/ensemble/guided_common.h"
#include "mutations/lens_perturbation.h"

namespace emlt {

class GuidedLensPerturbation final : public Mutation {
 public:
  explicit GuidedLensPerturbation(ensemble::InjectedBugs bugs = {}) : bugs_(bugs) {}
  std::string_view name() const override { return "emlt-lens"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override { return veach_.applies_to(x, ctx); }
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;

 private:
  LensPerturbation veach_;
  ensemble::InjectedBugs bugs_;
};

}  // namespace emlt
