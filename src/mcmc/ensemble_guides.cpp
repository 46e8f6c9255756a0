#include "emlt/mcmc/ensemble_guides.h"

#include "mutations/ensemble/adaptive_alpha.h"

namespace emlt {

void EnsembleGuides::build(std::span<const Path* const> paths, int width, int height, uint64_t seed,
                           const EnsembleParams& params) {
  params_ = params;
  seed_ = seed;
  paths_.clear();
  for (const Path* p : paths)
    if (p && !p->vertices.empty()) paths_.push_back(p);
  std::vector<PathType> types(paths_.size());
  std::vector<Vec2> raster(paths_.size());
  for (size_t i = 0; i < paths_.size(); ++i) {
    types[i] = paths_[i]->type;
    raster[i] = paths_[i]->raster();
  }
  index_.build(types);
  alpha_ = params.adaptive_alpha ? ensemble::adaptive_alpha(ensemble::image_coverage(raster, width, height))
                                 : params.alpha_fixed;
}

std::vector<const Path*> EnsembleGuides::upsilon(const PathType& type, uint64_t chain, uint64_t step) const {
  const std::vector<uint32_t> members = index_.guides(type, seed_, chain, step, params_.neighbours);
  std::vector<const Path*> out(members.size());
  for (size_t i = 0; i < members.size(); ++i) out[i] = paths_[members[i]];
  return out;
}

}  // namespace emlt
