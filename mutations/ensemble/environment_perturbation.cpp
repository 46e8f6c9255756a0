#include "mutations/ensemble/environment_perturbation.h"

#include "emlt/path/connection.h"
#include "mutations/perturbation_common.h"

namespace emlt {

namespace {
constexpr double kFallbackThetaMin = 1e-4, kFallbackThetaMax = 0.1;
}

bool EnvironmentPerturbation::applies_to(const Path& x, const MutationContext&) const {
  // The sky only: a directional light's one direction cannot move.
  return x.vertices.size() >= 3 && x.vertices[0].kind == VertexKind::Environment &&
         x.vertices[1].is_surface() && !x.vertices[1].delta;
}

std::optional<Path> EnvironmentPerturbation::with_sky_direction(const Path& x,
                                                                const Vec3& direction,
                                                                const MutationContext& ctx) {
  Path y = x;
  y.vertices[0] = make_environment_vertex(ctx.scene, direction);
  if (!mutually_visible(ctx.scene, y.vertices[1], y.vertices[0])) return std::nullopt;
  if (!perturbation::finish_proposal(ctx.scene, x, y)) return std::nullopt;
  return y;
}

std::optional<Proposal> EnvironmentPerturbation::propose(const Path& x, Rng& rng,
                                                         const MutationContext& ctx) const {
  // Only guides lit by the sky take part, weighted by the similarity of their x_1 to ours.
  // The move keeps every vertex but the sky's (and so the image point): y's Υ is x's, and
  // the kernels' reverse densities use the same guides and weights.
  const GuideView upsilon = ensemble::guides_for(x, ctx);
  ensemble::GuideBuffer<ensemble::SimilarityProduct> similarities(upsilon.size()),
      weights(upsilon.size());
  ensemble::GuideBuffer<Vec3> sky(upsilon.size());
  size_t count = 0;
  if (upsilon.has_environment()) {
    ensemble::path_similarities(x, upsilon, 1, 1, ensemble::similarity_params(ctx),
                                similarities.span());
    for (size_t n = 0; n < upsilon.size(); ++n)
      if (upsilon.environment(0)[n]) {
        weights[count] = similarities[n];
        sky[count++] = upsilon.sky_directions(0)[n];
      }
  }
  const std::span<const ensemble::SimilarityProduct> guide_weights = weights.span().first(count);
  const std::span<const Vec3> guide_sky = sky.span().first(count);
  const Vec3 current = x.vertices[0].sky_direction;
  Proposal proposal;
  Vec3 direction;
  double log_kernel_ratio = 0.0;
  if (count < 2) {
    direction = perturbation::perturb_direction(current, kFallbackThetaMin, kFallbackThetaMax,
                                                rng.uniform2());
    proposal.fallback = true;
  } else if (rng.uniform() < 0.5f) {
    const ensemble::GuideChoice choice = ensemble::choose_guide(guide_weights, rng);
    const auto step = ensemble::propose_great_arc(current, guide_sky[choice.index],
                                                  ensemble::stretch_params(upsilon), rng);
    if (!step.valid) return std::nullopt;
    direction = step.direction;
    log_kernel_ratio = step.log_density_ratio;
    proposal.alpha = upsilon.alpha();
  } else {
    ensemble::DirectionalParams params;
    params.similarity = ensemble::similarity_params(ctx);
    const auto step =
        ensemble::propose_directional(current, {guide_sky, {}, guide_weights}, params, rng);
    direction = step.direction;
    log_kernel_ratio = step.log_density_ratio();
  }
  auto y = with_sky_direction(x, direction, ctx);
  if (!y) return std::nullopt;
  proposal.path = std::move(*y);
  proposal.log_reverse_over_forward = bugs_.drop_reverse_density ? 0.0 : log_kernel_ratio;
  if (std::isnan(proposal.log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

}  // namespace emlt
