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
  bool upsilon_from_proposal = false;  // P(n|y) evaluated against the counter's Υ of y's next step
  bool reverse_upsilon_of_x = false;   // nearby Υ: the reverse move evaluated against x's Υ
  bool alpha_not_reversed = false;     // the reverse stretch density with x's Υ's α
  bool keep_degenerate_casts = false;  // ray-cast moves nearly parallel to the plane kept
};

// Υ of x at this step (empty without an ensemble).
GuideView guides_for(const Path& x, const MutationContext& ctx);
// Υ of the proposal y, against which the reverse move y -> x is evaluated: y's own nearby Υ,
// or x's (`forward`) when Υ is chosen by the counter; or as an injected bug chooses it.
GuideView reverse_guides_for(const Path& y, const GuideView& forward, const MutationContext& ctx,
                             const InjectedBugs& bugs = {});
// Υ by the counter whatever --ensemble-guides says, for the strategies whose densities need
// one Υ in both directions (density_jump_lens.h, spread_scaled_perturbation.h).
GuideView counter_guides_for(const Path& x, const MutationContext& ctx);

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
// The stretch move's distribution for a step guided by `guides` (§3.4's α of that Υ).
inline StretchParams stretch_params(const GuideView& guides) {
  StretchParams params;
  params.alpha = guides.alpha();
  return params;
}

// What the reverse move's stretch density changes when it is drawn with y's Υ's α rather
// than x's: log g_y(1/λ) - log g_x(1/λ), to add to a kernel's density ratio (which takes
// both from x's α). 0 when the two agree; -inf when 1/λ is outside y's support.
double stretch_reverse_correction(double lambda, const GuideView& forward, const GuideView& reverse,
                                  const InjectedBugs& bugs);

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
// the selection ratio: four logs a guided step were a tenth of its extra cost,
// docs/experiments.md, "Cost per mutation");
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

// log P(n | y) / P(n | x) for a guide `chosen` from x's Υ (`guides`) with similarity weights
// over [first, last], P(n | y) over y's Υ (`reverse`; -inf when it does not hold the guide);
// `rows_x`, when given, x's rows from choose_similar_guide (reused only when the two Υ are
// the same).
double log_selection_ratio(const Path& y, const GuideView& guides, const GuideView& reverse,
                           const SimilarGuide& chosen, int first, int last,
                           const MutationContext& ctx, const InjectedBugs& bugs,
                           const SimilarityRows* rows_x = nullptr);

}  // namespace emlt::ensemble
