#pragma once
// Veach's lens, caustic and multi-chain perturbations with their image-plane range scaled
// per path type by the frozen ensemble (`--mutations ...,emlt-spread-lens=W,
// emlt-spread-caustic=W,emlt-spread-multichain=W`). Veach's outer radius is fixed, 5 % of the
// image area (r_max = sqrt(0.05 W H / π), 32 px at 256×256), for every path; here it is the
// spread of Υ's image points (guide_spread.h: the per-axis standard deviation of where the
// ensemble's paths of x's type land), so a type confined to a small caustic takes small
// steps and a type spread over the whole image large ones. The caustic perturbation's angle
// range follows, since Veach derives it from the same radius.
//
// Why detailed balance holds: the inner perturbation's ratio is exact for any fixed range
// [r_min, r_max] (its 1/r density is symmetric when both moves use the same range), and
// r_max is a function of Υ alone, which the reverse move shares (the strategies keep the
// path type; Υ depends on the type, the chain and its step count). The range is clamped
// to [4 r_min, image diagonal]. With fewer than two guides the step is the plain one.
#include <memory>

#include "emlt/mcmc/mutation.h"

namespace emlt {

class SpreadScaledPerturbation final : public Mutation {
 public:
  // `inner` is one of Veach's perturbations (lens, caustic, multichain).
  SpreadScaledPerturbation(std::string name, std::unique_ptr<Mutation> inner);
  std::string_view name() const override { return name_; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override {
    return inner_->applies_to(x, ctx);
  }
  std::optional<Proposal> propose(const Path& x, Rng& rng,
                                  const MutationContext& ctx) const override;

 private:
  std::string name_;
  std::unique_ptr<Mutation> inner_;
};

}  // namespace emlt
