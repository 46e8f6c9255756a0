#include "mutations/ensemble/guided_multichain.h"

#include <array>
#include <span>

#include "emlt/path/path_density.h"

namespace emlt {

std::optional<Proposal> GuidedMultiChainPerturbation::propose(const Path& x, Rng& rng,
                                                              const MutationContext& ctx) const {
  const auto guides = ensemble::guides_for(x, ctx);
  if (guides.size() < 2) return ensemble::unguided_step(veach_, x, rng, ctx);
  const int l = MultiChainPerturbation::fixed_vertex(x.type);
  if (l < 0) return std::nullopt;
  const int first = l + 1, last = x.edges();
  ensemble::SimilarityRows rows;  // x's, reused for the reverse where y keeps a vertex
  const ensemble::SimilarGuide choice =
      ensemble::choose_similar_guide(x, guides, first, last, ctx, rng, &rows);
  const ensemble::StretchParams stretch = ensemble::stretch_params(guides);
  // Every stretch drawn (one per vertex at most), for the reverse α's correction.
  std::array<double, kMaxPathVertices> lambdas;
  size_t stretches = 0;

  const auto image_step =
      ensemble::propose_linear(x.raster(), guides.rasters()[choice.index], stretch, rng);
  if (!image_step.valid) return std::nullopt;
  double log_kernel_ratio = image_step.log_density_ratio;
  lambdas[stretches++] = image_step.lambda;
  std::vector<Vec3> directions;
  const auto& xv = x.vertices;
  for (int i = x.edges() - 1; i >= l + 2; --i) {
    if (xv[size_t(i)].delta) continue;
    const Vec3 current = direction_between(xv[size_t(i)], xv[size_t(i - 1)]);
    const Vec3 guide_direction =
        direction_between(ensemble::guide_vertex(guides, choice.index, i),
                          ensemble::guide_vertex(guides, choice.index, i - 1));
    const auto step = ensemble::propose_great_arc(current, guide_direction, stretch, rng);
    if (!step.valid) return std::nullopt;
    directions.push_back(step.direction);
    lambdas[stretches++] = step.lambda;
    log_kernel_ratio += step.log_density_ratio;
  }
  auto proposal = veach_.retrace(x, image_step.state, directions, ctx);
  if (!proposal) return std::nullopt;
  const GuideView reverse = ensemble::reverse_guides_for(proposal->path, guides, ctx, bugs_);
  for (const double lambda : std::span<const double>(lambdas.data(), stretches))
    log_kernel_ratio += ensemble::stretch_reverse_correction(lambda, guides, reverse, bugs_);
  proposal->log_reverse_over_forward +=
      (bugs_.drop_reverse_density ? 0.0 : log_kernel_ratio) +
      ensemble::log_selection_ratio(proposal->path, guides, reverse, choice, first, last, ctx,
                                    bugs_, &rows);
  proposal->alpha = guides.alpha();
  return proposal;
}

}  // namespace emlt
