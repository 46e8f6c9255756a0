#pragma once
// What EMLT's guided perturbations (Bashford-Rogers et al. 2021, §3.3) share: fetching Υ for
// the current step, the similarity and stretch parameters of this render, the
// similarity-weighted choice of one guide path, and the test switches that inject the
// bugs the statistical tests must catch.
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "emlt/mcmc/ensemble_guides.h"
#include "emlt/mcmc/mutation.h"
#include "mutations/ensemble/kernels.h"
#include "mutations/ensemble/similarity.h"

namespace emlt::ensemble {

// Deliberate errors for the tests (tests/statistical/emlt_test.cpp); never set otherwise.
struct InjectedBugs {
  bool drop_reverse_density = false;   // the kernel's T(y->x) replaced by T(x->y)
  bool sigma_not_refitted = false;     // reverse anisotropic density with x's Σ, recentred
  bool ignore_selection = false;       // P(n|y) / P(n|x) left out
  bool upsilon_from_proposal = false;  // P(n|y) evaluated against the Υ of y's next step
  bool keep_degenerate_casts = false;  // ray-cast moves nearly parallel to the plane kept
};

// Υ of x at this step (empty without an ensemble).
GuideView guides_for(const Path& x, const MutationContext& ctx);
// Υ as the buggy reverse evaluation would choose it (InjectedBugs::upsilon_from_proposal).
GuideView guides_for_next_step(const Path& y, const MutationContext& ctx);

// A step of the unguided strategy, marked as a fallback for the statistics (what a guided
// strategy does when Υ holds fewer than two paths).
std::optional<Proposal> unguided_step(const Mutation& fallback, const Path& x, Rng& rng,
                                      const MutationContext& ctx);

// Guide n's vertex i as far as direction_between reads it (whether it is a sky vertex, its
// position and its sky direction), from Υ's arrays: the guide's path is not touched.
PathVertex guide_vertex(const GuideView& guides, size_t n, int i);

inline SimilarityParams similarity_params(const MutationContext& ctx) {
  SimilarityParams params;
  if (ctx.ensemble && ctx.ensemble->params().similarity_length > 0.0)
    params.length_scale = ctx.ensemble->params().similarity_length;
  return params;
}
// The stretch move's distribution with this swap's α.
inline StretchParams stretch_params(const MutationContext& ctx) {
  StretchParams params;
  if (ctx.ensemble) params.alpha = ctx.ensemble->alpha();
  return params;
}

// out[n] = S(a, v^n_i) (eq. 8) for a path's vertex a at index i: points compared as points,
// a sky vertex (of the path or of a guide) as a direction; out.size() == guides.size().
void vertex_similarities(const PathVertex& a, const GuideView& guides, int i,
                         const SimilarityParams& params, std::span<double> out);

// out[n] = S(x, v^n, first, last) (eq. 9) over vertices [first, last] (same-type paths, so
// the indices correspond); out.size() == guides.size().
void path_similarities(const Path& x, const GuideView& guides, int first, int last,
                       const SimilarityParams& params, std::span<SimilarityProduct> out);

// The rows S(x_i, v^n_i) of one path, i in [first, last], kept from the guide choice for the
// reverse move: where the proposal leaves a vertex as it was (the fixed vertex of the
// caustic perturbation, a pinhole camera's lens point), its row is reused, not recomputed.
class SimilarityRows {
 public:
  SimilarityRows() = default;
  SimilarityRows(const SimilarityRows&) = delete;
  SimilarityRows& operator=(const SimilarityRows&) = delete;

  void assign(const Path& path, int first, int last, size_t guides);
  std::span<double> row(int i) { return {data_ + size_t(i - first_) * guides_, guides_}; }
  // The row of vertex i of `other` if it equals the kept path's vertex i (an empty span if
  // not): vertex_similarities reads only what is compared here.
  std::span<const double> reusable_row(const Path& other, int i) const;

 private:
  static constexpr size_t kStackEntries = 512;  // 8 guides of 64 vertices
  const Path* path_ = nullptr;
  int first_ = 0, last_ = -1;
  size_t guides_ = 0;
  double* data_ = nullptr;
  std::array<double, kStackEntries> stack_;  // left uninitialised
  std::vector<double> heap_;
};

// A guide drawn with P(n | x) proportional to S(x, v^n, first, last) (eq. 9). Where every
// weight was a plain double, P(n | x) is kept as weight / total (the logs are taken once, in
// the selection ratio: four logs a guided step were a tenth of its extra cost, issue 21);
// else as log_probability.
struct SimilarGuide {
  uint32_t index = 0;
  double weight = 0.0, total = 0.0;  // total > 0: P(index | x) = weight / total
  double log_probability = 0.0;      // otherwise: log P(index | x)
  double log_p() const {
    return total > 0.0 ? std::log(weight) - std::log(total) : log_probability;
  }
};

// One guide drawn with P(n | x) proportional to S(x, v^n, first, last) (eq. 9); with `rows`,
// x's rows are kept there.
SimilarGuide choose_similar_guide(const Path& x, const GuideView& guides, int first, int last,
                                  const MutationContext& ctx, Rng& rng,
                                  SimilarityRows* rows = nullptr);

// log P(n | y) / P(n | x) for a guide `chosen` for x with similarity weights over [first,
// last]; `rows_x`, when given, x's rows from choose_similar_guide (the same Υ).
double log_selection_ratio(const Path& y, const GuideView& guides, const SimilarGuide& chosen,
                           int first, int last, const MutationContext& ctx,
                           const InjectedBugs& bugs, const SimilarityRows* rows_x = nullptr);

}  // namespace emlt::ensemble
