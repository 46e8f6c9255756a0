#pragma once
// The frozen complementary ensemble Y as EMLT's guided strategies see it (Bashford-Rogers et
// al. 2021, §3.1): Y's paths, the path-type tree over them, and the quantities derived from
// Y once per swap (the linear kernels' α, §3.4). A strategy asks for Υ, the guide paths of
// its current path's type; the choice depends on (type, seed, chain, step) only, so the
// forward and reverse densities of one step are evaluated against the same Υ
// (emlt-notes.md §2).
#include <cstdint>
#include <span>
#include <vector>

#include "emlt/mcmc/path_type_index.h"
#include "emlt/path/path.h"

namespace emlt {

struct EnsembleParams {
  int neighbours = 32;  // M, the size of Υ (--ensemble-neighbours)
  // Length (scene units) below which two vertices count as the same in the similarity of
  // eq. 8; 0 = the paper's literal form, distances in scene units unscaled.
  double similarity_length = 0.0;
  // The adaptive α of the linear kernels (§3.4); false keeps alpha_fixed.
  bool adaptive_alpha = true;
  double alpha_fixed = 0.5;
};

class EnsembleGuides {
 public:
  // Rebuilds from Y (null paths, chains without a seed, are left out). `seed` keys the
  // deterministic choice of Υ.
  void build(std::span<const Path* const> paths, int width, int height, uint64_t seed,
             const EnsembleParams& params);

  // Υ for a path of this type at this chain's step: up to M paths of Y of the same type.
  std::vector<const Path*> upsilon(const PathType& type, uint64_t chain, uint64_t step) const;

  const EnsembleParams& params() const { return params_; }
  double alpha() const { return alpha_; }
  size_t size() const { return paths_.size(); }

 private:
  std::vector<const Path*> paths_;
  PathTypeIndex index_;
  EnsembleParams params_;
  uint64_t seed_ = 0;
  double alpha_ = 0.5;
};

}  // namespace emlt
