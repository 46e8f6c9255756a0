#pragma once
// A jump to where the complementary ensemble is: an independence proposal in a 2-D space
// (the image plane) drawn from a kernel density estimate over the guide points of Υ,
//     q(u) = (1/M) Σ_n N(u; v_n, h² I),   h = max(spread(Υ) · M^(-1/6), h_min)
// (Scott's rule in two dimensions on the guides' per-axis spread, guide_spread.h). The
// guides are drawn from the frozen ensemble, which samples the chains' target, so q is a
// rough fit of the target's marginal there: accepted jumps cross the image in one step,
// where a perturbation diffuses. q does not depend on the current point, so
//     T(x -> y) = q(u_y),  T(y -> x) = q(u_x),  log T(y->x)/T(x->y) = log q(u_x) - log q(u_y),
// valid as long as q is a function of Υ only (the same Υ for the forward and the reverse
// move: Υ depends on the path type, which the strategy keeps, and on (chain, step)).
// Checked alone on an analytic target in tests/statistical/ensemble_ideas_test.cpp.
#include <span>

#include "emlt/core/math.h"
#include "emlt/core/rng.h"

namespace emlt::ensemble {

// Weighted variant: component n drawn with probability w_n / Σ w (the bandwidth stays the
// unweighted one). Valid under the same condition: the weights, like Υ, must be the same for
// the forward and the reverse move, e.g. functions of a vertex the move keeps (DensityJumpLens
// weighs the guides by the similarity of their vertex l to the fixed x_l).
struct GuideMixture {
  std::span<const Vec2> centres;
  double bandwidth = 1.0;
  std::span<const double> weights;  // empty: uniform
  double weight_total = 0.0;
};

// The mixture over `centres` with Scott's bandwidth, at least min_bandwidth; `weights`
// (optional, one per centre, >= 0) are used when their sum is positive and finite.
GuideMixture fit_guide_mixture(std::span<const Vec2> centres, double min_bandwidth,
                               std::span<const double> weights = {});

Vec2 sample_guide_mixture(const GuideMixture& mixture, Rng& rng);
// log q(u) (log-sum-exp over the components: far from every guide it stays finite).
double guide_mixture_log_density(const GuideMixture& mixture, const Vec2& u);

struct JumpProposal {
  Vec2 state{0.0f};
  double log_density_ratio = 0.0;  // log q(u_x) - log q(u_y)
};

JumpProposal propose_jump(const Vec2& x, const GuideMixture& mixture, Rng& rng);

}  // namespace emlt::ensemble
