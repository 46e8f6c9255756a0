#pragma once
// Metropolis-Hastings acceptance, in one stage or in two (delayed acceptance, Christen and
// Fox 2005), for the MLT driver's step (mlt_step.cpp).
//
// Two stages. A strategy may leave a costly factor out of its proposal's ratio
// (Proposal::deferred: the geometry-aware strategies' ranges at y, which need y's cones). The
// first stage accepts with a1 = min(1, r1), r1 the ratio without that factor; only then is
// the factor d = r / r1 evaluated and the second stage accepts with a2 = min(1, d). The
// product satisfies detailed balance provided r1(y, x) = 1 / r1(x, y): then
//   f(x) T(x->y) a1(x,y) a2(x,y) = f(x) T(x->y) min(1, r1) min(1, r / r1)
// is symmetric in x and y (r = f(y) T(y->x) / (f(x) T(x->y)) turns into 1/r, r1 into 1/r1,
// and f(x) T(x->y) into f(y) T(y->x) = r f(x) T(x->y); the four cases of the two minima
// check out alike). The acceptance falls (a1 a2 <= min(1, r)), so a chain moves less per
// step; in exchange a proposal turned down by the first stage never pays for the factor.
//
// One uniform u decides both: the first stage passes when u < a1, and given that u / a1 is
// uniform, so the second passes when u < a1 a2. The chain's random numbers are then the same
// as with one stage.
//
// Expected values: the proposal's splat weight is 1{u < a1} a2, whose expectation over u is
// the acceptance probability a1 a2, and the current path's is one minus it; unbiased like
// Veach's weights, and a2 is needed only where the first stage passed.
#include <algorithm>
#include <cmath>

namespace emlt {

// min(1, ratio), with a ratio that overflowed to +infinity accepted and NaN rejected.
inline double acceptance_probability(double ratio) {
  return std::isfinite(ratio) ? std::clamp(ratio, 0.0, 1.0) : (ratio > 0.0 ? 1.0 : 0.0);
}

// A two-stage step: the proposal's expected-value weight 1{u < a1} a2 and the threshold a1 a2
// below which u accepts it (0 when the first stage fails), from the first stage's ratio r1,
// the step's uniform u and a callable giving the deferred factor's log, called only when the
// first stage passes. second_stage_uses_whole_ratio is an injected bug for the tests: a2 =
// min(1, r) instead of min(1, r / r1), which counts r1 twice.
struct TwoStageDecision {
  double weight = 0.0;
  double accept_below = 0.0;
};
template <typename Deferred>
TwoStageDecision two_stage_decision(double first_ratio, double u, Deferred&& log_deferred,
                                    bool second_stage_uses_whole_ratio = false) {
  const double a1 = acceptance_probability(first_ratio);
  if (!(u < a1)) return {};
  const double factor = std::exp(log_deferred());
  const double a2 =
      acceptance_probability(second_stage_uses_whole_ratio ? first_ratio * factor : factor);
  return {a2, a1 * a2};
}

}  // namespace emlt
