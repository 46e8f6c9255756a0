// The shared Gauss–Legendre rule (core/gauss_legendre.h): nodes increasing and symmetric,
// and exact for every monomial up to degree 2n - 1 on [-1, 1], as an n-point rule must be.
#include "emlt/core/gauss_legendre.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace emlt;

TEST(GaussLegendre, ExactUpToDegreeTwoNMinusOne) {
  for (const int n : {1, 2, 5, 8, 16, 32}) {
    const GaussLegendreRule rule = gauss_legendre(n);
    ASSERT_EQ(rule.x.size(), size_t(n));
    for (int i = 0; i < n; ++i) {
      if (i > 0) {
        EXPECT_LT(rule.x[size_t(i - 1)], rule.x[size_t(i)]) << n;
      }
      EXPECT_DOUBLE_EQ(rule.x[size_t(i)], -rule.x[size_t(n - 1 - i)]) << n;
    }
    for (int k = 0; k <= 2 * n - 1; ++k) {
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += rule.w[size_t(i)] * std::pow(rule.x[size_t(i)], k);
      const double exact = k % 2 ? 0.0 : 2.0 / (k + 1);
      EXPECT_NEAR(sum, exact, 1e-13) << "n " << n << ", x^" << k;
    }
    // Degree 2n is beyond the rule: it must miss (so the test can tell a rule of more points;
    // for many points the miss falls below round-off).
    if (n > 8) continue;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += rule.w[size_t(i)] * std::pow(rule.x[size_t(i)], 2 * n);
    EXPECT_GT(std::abs(sum - 2.0 / (2 * n + 1)), 1e-6) << n;
  }
}
