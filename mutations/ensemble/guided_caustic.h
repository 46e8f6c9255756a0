#pragma once
// EMLT's linear caustic perturbation (Bashford-Rogers et al. 2021, §3.3): on the paths of
// Veach's caustic perturbation ((L|D) S* D E eye ends), the direction leaving the fixed
// vertex x_l moves along the great arc towards ω2 = x_l -> v_{l+1}, the direction from x_l
// to a guide's first vertex after it (the hemispherical kernel, kernels.h). The guide is
// drawn in proportion to the similarity of x_l and x_{l+1} to the guide's (eq. 9: "the
// starting point and first specular vertex"). x_l is fixed, so ω2 is the same when the
// reverse move starts from y. The specular chain and the connection to the eye are
// Veach's deterministic retrace, whose Jacobians CausticPerturbation::retrace reports:
//   log T(y->x)/T(x->y) = retrace ratio + great-arc ratio + log P(n|y) - log P(n|x).
// Fewer than two guides: Veach's caustic perturbation.
#include "mutations/caustic_perturbation.h"
#include "mutations/ensemble/guided_common.h"

namespace emlt {

class GuidedCausticPerturbation final : public Mutation {
 public:
  explicit GuidedCausticPerturbation(ensemble::InjectedBugs bugs = {}) : bugs_(bugs) {}
  std::string_view name() const override { return "emlt-caustic"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override { return veach_.applies_to(x, ctx); }
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;

 private:
  CausticPerturbation veach_;
  ensemble::InjectedBugs bugs_;
};

}  // namespace emlt
