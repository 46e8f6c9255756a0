#include "mutations/ensemble/guided_lens.h"

namespace emlt {

std::optional<Proposal> GuidedLensPerturbation::propose(const Path& x, Rng& rng,
                                                        const MutationContext& ctx) const {
  const auto guides = ensemble::guides_for(x, ctx);
  if (guides.size() < 2) return ensemble::unguided_step(veach_, x, rng, ctx);
  const int first = LensPerturbation::fixed_vertex(x.type) + 1, last = x.edges();
  ensemble::SimilarityRows rows;  // x's, reused for the reverse where y keeps a vertex
  const ensemble::SimilarGuide choice =
      ensemble::choose_similar_guide(x, guides, first, last, ctx, rng, &rows);
  const auto step = ensemble::propose_linear(x.raster(), guides.rasters()[choice.index],
                                             ensemble::stretch_params(guides), rng);
  if (!step.valid) return std::nullopt;
  auto proposal = veach_.perturb_to(x, step.state, ctx);
  if (!proposal) return std::nullopt;
  const GuideView reverse = ensemble::reverse_guides_for(proposal->path, guides, ctx, bugs_);
  proposal->log_reverse_over_forward +=
      (bugs_.drop_reverse_density
           ? 0.0
           : step.log_density_ratio +
                 ensemble::stretch_reverse_correction(step.lambda, guides, reverse, bugs_)) +
      ensemble::log_selection_ratio(proposal->path, guides, reverse, choice, first, last, ctx,
                                    bugs_, &rows);
  proposal->alpha = guides.alpha();
  return proposal;
}

}  // namespace emlt
