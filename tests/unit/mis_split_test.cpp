// The MIS heuristics' weights and Lu's second-order split estimate (sampling/mis.h,
// sampling/second_order_alpha.h) on one-dimensional problems whose integrals are known.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "emlt/core/rng.h"
#include "emlt/sampling/mis.h"
#include "emlt/sampling/second_order_alpha.h"

using namespace emlt;

TEST(MisHeuristics, TwoStrategiesWeightsSumToOne) {
  Rng rng(3, 0);
  for (MisHeuristic h :
       {MisHeuristic::Balance, MisHeuristic::Power, MisHeuristic::Max, MisHeuristic::SecondOrder}) {
    for (int i = 0; i < 10000; ++i) {
      // Densities over many decades, with exact zeros and ties among them.
      const auto draw = [&] {
        const float u = rng.uniform();
        return u < 0.1f ? 0.0f : u < 0.2f ? 1.0f : std::exp(40.0f * (rng.uniform() - 0.5f));
      };
      const float a = draw(), b = draw();
      if (a == 0.0f && b == 0.0f) continue;
      EXPECT_NEAR(mis_weight(h, a, b) + mis_weight(h, b, a), 1.0f, 1e-6f)
          << to_string(h) << " " << a << " " << b;
    }
  }
}

TEST(MisHeuristics, MaxGivesEverythingToTheLargerDensity) {
  EXPECT_EQ(max_heuristic(1.0f, 2.0f, 1.0f, 1.0f), 1.0f);
  EXPECT_EQ(max_heuristic(1.0f, 1.0f, 1.0f, 2.0f), 0.0f);
  EXPECT_EQ(max_heuristic(1.0f, 3.0f, 1.0f, 3.0f), 0.5f);  // a tie shared
  EXPECT_EQ(max_heuristic(3.0f, 1.0f, 1.0f, 2.0f), 1.0f);  // counts included
  // Second-order weighs a fixed pair as the balance heuristic (the mixture at alpha 1/2).
  EXPECT_EQ(mis_weight(MisHeuristic::SecondOrder, 0.3f, 0.9f),
            mis_weight(MisHeuristic::Balance, 0.3f, 0.9f));
}

namespace {

// A unit-area tent of half-width w about 1/2 on [0, 1], and a draw from it.
double tent(double x, double w) {
  const double d = std::abs(x - 0.5);
  return d < w ? (w - d) / (w * w) : 0.0;
}
double draw_tent(Rng& rng, double w) {
  return 0.5 + w * (rng.uniform_double() + rng.uniform_double() - 1.0);
}

// Eq. 5.4 by the midpoint rule, for light density pl, BSDF density pb and integrand f.
double quadrature_alpha(const std::function<double(double)>& f,
                        const std::function<double(double)>& pl,
                        const std::function<double(double)>& pb) {
  const int cells = 400000;
  double first = 0.0, second = 0.0;
  for (int i = 0; i < cells; ++i) {
    const double x = (i + 0.5) / cells, mean = 0.5 * (pl(x) + pb(x)), d = 0.5 * (pl(x) - pb(x));
    if (!(mean > 0.0)) continue;
    first += f(x) * f(x) * d / (mean * mean);
    second += f(x) * f(x) * d * d / (mean * mean * mean);
  }
  return 0.25 * (2.0 + first / second);
}

// Eq. 5.5 from `pairs` light and BSDF draws.
SecondOrderAlpha pilot(const std::function<double(double)>& f,
                       const std::function<double(double)>& pl,
                       const std::function<double(double)>& pb,
                       const std::function<double(Rng&)>& draw_light,
                       const std::function<double(Rng&)>& draw_bsdf, int pairs) {
  SecondOrderAlpha moments;
  Rng rng(11, 0);
  for (int i = 0; i < pairs; ++i)
    for (double x : {draw_light(rng), draw_bsdf(rng)}) moments.add(f(x), pl(x), pb(x));
  return moments;
}

}  // namespace

TEST(SecondOrderAlpha, EstimateConvergesToEquation54) {
  // Integrand: a wide tent times a ramp; light density uniform, BSDF density a tent. The
  // estimate from pilot draws matches Eq. 5.4 integrated by quadrature.
  for (double w : {0.5, 0.2, 0.05}) {
    const auto f = [](double x) { return tent(x, 0.45) * (0.2 + x); };
    const auto pl = [](double) { return 1.0; };
    const auto pb = [w](double x) { return tent(x, w); };
    const double expected = quadrature_alpha(f, pl, pb);
    const SecondOrderAlpha m = pilot(
        f, pl, pb, [](Rng& r) { return r.uniform_double(); },
        [w](Rng& r) { return draw_tent(r, w); }, 200000);
    EXPECT_NEAR(m.unclamped(), expected, 0.01 * std::max(1.0, std::abs(expected))) << w;
  }
}

TEST(SecondOrderAlpha, ExtremeCasesStopAtAQuarterAndThreeQuarters) {
  // Section 5.3.4: an integrand that is the BSDF lobe itself (a mirror, in the limit) drives
  // the light share to 1/4, not 0; a Dirac-like light to 3/4, not 1.
  const double w = 1e-3;
  const auto lobe = [w](double x) { return tent(x, w); };
  const auto uniform = [](double) { return 1.0; };
  const auto draw_uniform = [](Rng& r) { return r.uniform_double(); };
  const auto draw_lobe = [w](Rng& r) { return draw_tent(r, w); };
  const SecondOrderAlpha mirror = pilot(lobe, uniform, lobe, draw_uniform, draw_lobe, 20000);
  EXPECT_NEAR(mirror.unclamped(), 0.25, 0.01);
  const SecondOrderAlpha dirac = pilot(lobe, lobe, uniform, draw_lobe, draw_uniform, 20000);
  EXPECT_NEAR(dirac.unclamped(), 0.75, 0.01);
  // The clamp of Fig. 5.4 and the balance heuristic's 1/2 when nothing was seen.
  SecondOrderAlpha beyond;
  beyond.add(1.0, 1.0, 0.9);  // dp / pbar small and positive: Eq. 5.4 far above 1
  EXPECT_GT(beyond.unclamped(), 1.0);
  EXPECT_DOUBLE_EQ(beyond.alpha(0.025), 0.975);
  EXPECT_DOUBLE_EQ(SecondOrderAlpha().alpha(0.025), 0.5);
}
