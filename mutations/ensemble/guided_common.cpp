#include "mutations/ensemble/guided_common.h"

namespace emlt::ensemble {

std::vector<const Path*> guides_for(const Path& x, const MutationContext& ctx) {
  if (!ctx.ensemble) return {};
  return ctx.ensemble->upsilon(x.type, ctx.chain, ctx.step);
}

std::vector<const Path*> guides_for_next_step(const Path& y, const MutationContext& ctx) {
  if (!ctx.ensemble) return {};
  return ctx.ensemble->upsilon(y.type, ctx.chain, ctx.step + 1);
}

std::optional<Proposal> unguided_step(const Mutation& fallback, const Path& x, Rng& rng,
                                      const MutationContext& ctx) {
  auto proposal = fallback.propose(x, rng, ctx);
  if (proposal) proposal->fallback = true;
  return proposal;
}

SimilarityParams similarity_params(const MutationContext& ctx) {
  SimilarityParams params;
  if (ctx.ensemble && ctx.ensemble->params().similarity_length > 0.0)
    params.length_scale = ctx.ensemble->params().similarity_length;
  return params;
}

StretchParams stretch_params(const MutationContext& ctx) {
  StretchParams params;
  if (ctx.ensemble) params.alpha = ctx.ensemble->alpha();
  return params;
}

void log_path_similarities(const Path& x, std::span<const Path* const> guides, int first, int last,
                           const SimilarityParams& params, std::vector<double>& out) {
  out.assign(guides.size(), 0.0);
  for (size_t n = 0; n < guides.size(); ++n)
    for (int i = first; i <= last; ++i) {
      const PathVertex &a = x.vertices[size_t(i)], &b = guides[n]->vertices[size_t(i)];
      // A sky vertex is a direction: compare directions (unit vectors) instead of points.
      out[n] += a.is_environment() || b.is_environment()
                    ? log_vertex_similarity(a.sky_direction, b.sky_direction, params)
                    : log_vertex_similarity(a.position, b.position, params);
    }
}

GuideChoice choose_similar_guide(const Path& x, std::span<const Path* const> guides, int first, int last,
                                 const MutationContext& ctx, Rng& rng) {
  std::vector<double> weights;
  log_path_similarities(x, guides, first, last, similarity_params(ctx), weights);
  return choose_guide(weights, rng);
}

double log_selection_ratio(const Path& y, std::span<const Path* const> guides, uint32_t index,
                           double log_probability_x, int first, int last, const MutationContext& ctx,
                           const InjectedBugs& bugs) {
  if (bugs.ignore_selection) return 0.0;
  std::vector<double> weights;
  if (bugs.upsilon_from_proposal) {
    const auto other = guides_for_next_step(y, ctx);
    if (index >= other.size()) return 0.0;
    log_path_similarities(y, other, first, last, similarity_params(ctx), weights);
  } else {
    log_path_similarities(y, guides, first, last, similarity_params(ctx), weights);
  }
  return guide_log_probability(weights, index) - log_probability_x;
}

}  // namespace emlt::ensemble
