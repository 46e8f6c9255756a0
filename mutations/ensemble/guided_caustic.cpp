#include "mutations/ensemble/guided_caustic.h"

namespace emlt {

std::optional<Proposal> GuidedCausticPerturbation::propose(const Path& x, Rng& rng,
                                                           const MutationContext& ctx) const {
  const auto guides = ensemble::guides_for(x, ctx);
  if (guides.size() < 2) return ensemble::unguided_step(veach_, x, rng, ctx);
  const int l = CausticPerturbation::fixed_vertex(x.type);
  if (l < 0) return std::nullopt;
  ensemble::SimilarityRows rows;  // x's, reused for the reverse where y keeps a vertex
  const ensemble::SimilarGuide choice =
      ensemble::choose_similar_guide(x, guides, l, l + 1, ctx, rng, &rows);
  const PathVertex& fixed = x.vertices[size_t(l)];
  const Vec3 current = direction_between(fixed, x.vertices[size_t(l + 1)]);
  const Vec3 towards_guide =
      direction_between(fixed, ensemble::guide_vertex(guides, choice.index, l + 1));
  const auto step =
      ensemble::propose_great_arc(current, towards_guide, ensemble::stretch_params(guides), rng);
  if (!step.valid) return std::nullopt;
  auto proposal = veach_.retrace(x, step.direction, ctx);
  if (!proposal) return std::nullopt;
  const GuideView reverse = ensemble::reverse_guides_for(proposal->path, guides, ctx, bugs_);
  proposal->log_reverse_over_forward +=
      (bugs_.drop_reverse_density
           ? 0.0
           : step.log_density_ratio +
                 ensemble::stretch_reverse_correction(step.lambda, guides, reverse, bugs_)) +
      ensemble::log_selection_ratio(proposal->path, guides, reverse, choice, l, l + 1, ctx, bugs_,
                                    &rows);
  proposal->alpha = guides.alpha();
  return proposal;
}

}  // namespace emlt
