#include "mutations/ensemble/density_jump_lens.h"

#include "mutations/ensemble/density_jump.h"
#include "mutations/ensemble/guided_common.h"

namespace emlt {

namespace {
// The narrowest kernel (pixels): below a pixel the jump would be a lens perturbation.
constexpr double kMinBandwidth = 1.0;
// Υ sizes up to which emlt-jump-near weighs its guides (beyond, uniform: --ensemble-neighbours
// is 8 by default).
constexpr size_t kMaxWeightedGuides = 256;
}  // namespace

std::optional<Proposal> DensityJumpLens::propose(const Path& x, Rng& rng,
                                                 const MutationContext& ctx) const {
  const auto guides = ensemble::counter_guides_for(x, ctx);
  if (guides.size() < 2) return ensemble::unguided_step(veach_, x, rng, ctx);
  double weights[kMaxWeightedGuides];
  std::span<const double> used;
  if (near_fixed_vertex_ && guides.size() <= kMaxWeightedGuides) {
    const int l = LensPerturbation::fixed_vertex(x.type);
    if (l < 0) return std::nullopt;
    const std::span<double> row(weights, guides.size());
    ensemble::vertex_similarities(x.vertices[size_t(l)], guides, l,
                                  ensemble::similarity_params(ctx), row);
    used = row;
  }
  const auto mixture = ensemble::fit_guide_mixture(guides.rasters(), kMinBandwidth, used);
  const auto jump = ensemble::propose_jump(x.raster(), mixture, rng);
  auto proposal = veach_.perturb_to(x, jump.state, ctx);
  if (!proposal) return std::nullopt;
  if (!drop_density_ratio_) proposal->log_reverse_over_forward += jump.log_density_ratio;
  return proposal;
}

}  // namespace emlt
