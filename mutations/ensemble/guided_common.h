#pragma once
// What EMLT's guided perturbations (Bashford-Rogers et al. 2021, §3.3) share: fetching Υ for
// the current step, the similarity and stretch parameters of this render, the
// similarity-weighted choice of one guide path, and the test switches that inject the
// bugs the statistical tests must catch.
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

SimilarityParams similarity_params(const MutationContext& ctx);
// The stretch move's distribution with this swap's α.
StretchParams stretch_params(const MutationContext& ctx);

// out[n] = S(a, v^n_i) (eq. 8) for a path's vertex a at index i: points compared as points,
// a sky vertex (of the path or of a guide) as a direction; out.size() == guides.size().
void vertex_similarities(const PathVertex& a, const GuideView& guides, int i,
                         const SimilarityParams& params, std::span<double> out);

// out[n] = S(x, v^n, first, last) (eq. 9) over vertices [first, last] (same-type paths, so
// the indices correspond); out.size() == guides.size().
void path_similarities(const Path& x, const GuideView& guides, int first, int last,
                       const SimilarityParams& params, std::span<SimilarityProduct> out);

// One guide drawn with P(n | x) proportional to S(x, v^n, first, last) (eq. 9).
GuideChoice choose_similar_guide(const Path& x, const GuideView& guides, int first, int last,
                                 const MutationContext& ctx, Rng& rng);

// log P(n | y) / P(n | x) for a guide chosen with similarity weights over [first, last];
// `log_probability_x` is what choose_guide reported for x.
double log_selection_ratio(const Path& y, const GuideView& guides, uint32_t index,
                           double log_probability_x, int first, int last,
                           const MutationContext& ctx, const InjectedBugs& bugs);

}  // namespace emlt::ensemble
