#pragma once
// EMLT's environment perturbation (Bashford-Rogers et al. 2021, §3.3, Fig. 11): for paths
// lit by the sky whose first vertex x_1 is non-specular, the direction from x_1 to the sky
// (the sky vertex x_0 itself, measured in solid angle) moves towards the guides' sky
// directions, with probability 1/2 each by
//   the great-arc kernel towards one guide's sky direction, the guide drawn in proportion
//     to the similarity of its x_1 to ours (x_1 does not move, so P(n|y) = P(n|x)), or
//   the directional kernel: a vMF recentred on our direction, its concentration fitted to
//     the guides' sky directions weighted by that similarity (eq. 11) and by their
//     closeness to our direction (so it is refitted at the proposed direction in reverse).
// Only guides lit by the sky take part (the path type does not tell sky from area light).
// With fewer than two such guides the step turns the direction by Veach's 1/θ offset in a
// fixed range [1e-4, 0.1] rad, symmetric in solid angle.
// The kernel choice does not depend on the state, so it cancels; nothing else moves, so
//   log T(y->x)/T(x->y) = the kernel's ratio (+ the selection ratio, zero here).
// Paper §4.3 uses it with the linear lens perturbation for environment-lit direct light
// (`--direct mlt --mutations bidir=1,emlt-lens=1,emlt-env=1`).
#include "mutations/ensemble/guided_common.h"

namespace emlt {

class EnvironmentPerturbation final : public Mutation {
 public:
  explicit EnvironmentPerturbation(ensemble::InjectedBugs bugs = {}) : bugs_(bugs) {}
  std::string_view name() const override { return "emlt-env"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override;
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;

  // The deterministic part: x with the sky direction replaced (empty when x_1 cannot see
  // the sky that way, or the path's type would change).
  static std::optional<Path> with_sky_direction(const Path& x, const Vec3& direction, const MutationContext& ctx);

 private:
  ensemble::InjectedBugs bugs_;
};

}  // namespace emlt
