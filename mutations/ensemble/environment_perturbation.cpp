#include "mutations/ensemble/environment_perturbation.h"

#include "emlt/path/connection.h"
#include "mutations/perturbation_common.h"

namespace emlt {

namespace {
constexpr double kFallbackThetaMin = 1e-4, kFallbackThetaMax = 0.1;
}

bool EnvironmentPerturbation::applies_to(const Path& x, const MutationContext&) const {
  return x.vertices.size() >= 3 && x.vertices[0].is_environment() && x.vertices[1].is_surface() &&
         !x.vertices[1].delta;
}

std::optional<Path> EnvironmentPerturbation::with_sky_direction(const Path& x, const Vec3& direction,
                                                                const MutationContext& ctx) {
  Path y = x;
  y.vertices[0] = make_environment_vertex(ctx.scene, direction);
  if (!mutually_visible(ctx.scene, y.vertices[1], y.vertices[0])) return std::nullopt;
  if (!perturbation::finish_proposal(ctx.scene, x, y)) return std::nullopt;
  return y;
}

std::optional<Proposal> EnvironmentPerturbation::propose(const Path& x, Rng& rng,
                                                         const MutationContext& ctx) const {
  std::vector<const Path*> guides;
  for (const Path* g : ensemble::guides_for(x, ctx))
    if (g->vertices[0].is_environment()) guides.push_back(g);
  const Vec3 current = x.vertices[0].sky_direction;
  Proposal proposal;
  Vec3 direction;
  double log_kernel_ratio = 0.0;
  if (guides.size() < 2) {
    direction = perturbation::perturb_direction(current, kFallbackThetaMin, kFallbackThetaMax, rng.uniform2());
    proposal.fallback = true;
  } else {
    std::vector<double> weights;
    ensemble::log_path_similarities(x, guides, 1, 1, ensemble::similarity_params(ctx), weights);
    if (rng.uniform() < 0.5f) {
      const ensemble::GuideChoice choice = ensemble::choose_guide(weights, rng);
      const auto step = ensemble::propose_great_arc(current, guides[choice.index]->vertices[0].sky_direction,
                                                    ensemble::stretch_params(ctx), rng);
      if (!step.valid) return std::nullopt;
      direction = step.direction;
      log_kernel_ratio = step.log_density_ratio;
    } else {
      std::vector<Vec3> sky;
      for (const Path* g : guides) sky.push_back(g->vertices[0].sky_direction);
      ensemble::DirectionalParams params;
      params.similarity = ensemble::similarity_params(ctx);
      const auto step = ensemble::propose_directional(current, {sky, weights}, params, rng);
      direction = step.direction;
      log_kernel_ratio = step.log_density_ratio();
    }
  }
  auto y = with_sky_direction(x, direction, ctx);
  if (!y) return std::nullopt;
  proposal.path = std::move(*y);
  proposal.log_reverse_over_forward = bugs_.drop_reverse_density ? 0.0 : log_kernel_ratio;
  if (std::isnan(proposal.log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

}  // namespace emlt
