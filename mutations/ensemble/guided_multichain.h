#pragma once
// EMLT's linear multi-chain perturbation (Bashford-Rogers et al. 2021, §3.3): on the paths
// of Veach's multi-chain perturbation ((L|D) D (S+ D)+ S* E eye ends), one guide v^n drawn
// in proportion to the similarity of the eye subpath [x_{l+1}, x_k] moves the image point
// with the linear kernel (as the linear lens perturbation) and, at every interior
// non-specular vertex x_i, the outgoing direction along the great arc towards the guide's
// own outgoing direction there (v_i -> v_{i-1}; a property of the guide alone, so the
// reverse step moves along the same great circle). Each kernel draws its own λ. The walk
// through the specular chains and the final connection are Veach's deterministic retrace:
//   log T(y->x)/T(x->y) = retrace ratio + linear ratio + Σ great-arc ratios
//                       + log P(n|y) - log P(n|x).
// Fewer than two guides: Veach's multi-chain perturbation.
#include "mutations/ensemble/guided_common.h"
#include "mutations/multichain_perturbation.h"

namespace emlt {

class GuidedMultiChainPerturbation final : public Mutation {
 public:
  explicit GuidedMultiChainPerturbation(ensemble::InjectedBugs bugs = {}) : bugs_(bugs) {}
  std::string_view name() const override { return "emlt-multichain"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override { return veach_.applies_to(x, ctx); }
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;

 private:
  MultiChainPerturbation veach_;
  ensemble::InjectedBugs bugs_;
};

}  // namespace emlt
