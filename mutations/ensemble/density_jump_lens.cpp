#include "mutations/ensemble/density_jump_lens.h"

#include "mutations/ensemble/density_jump.h"
#include "mutations/ensemble/guided_common.h"

namespace emlt {

namespace {
// The narrowest kernel (pixels): below a pixel the jump would be a lens perturbation.
constexpr double kMinBandwidth = 1.0;
}  // namespace

std::optional<Proposal> DensityJumpLens::propose(const Path& x, Rng& rng,
                                                 const MutationContext& ctx) const {
  const auto guides = ensemble::guides_for(x, ctx);
  if (guides.size() < 2) return ensemble::unguided_step(veach_, x, rng, ctx);
  const auto mixture = ensemble::fit_guide_mixture(guides.rasters(), kMinBandwidth);
  const auto jump = ensemble::propose_jump(x.raster(), mixture, rng);
  auto proposal = veach_.perturb_to(x, jump.state, ctx);
  if (!proposal) return std::nullopt;
  if (!drop_density_ratio_) proposal->log_reverse_over_forward += jump.log_density_ratio;
  return proposal;
}

}  // namespace emlt
