#include "emlt/core/gauss_legendre.h"

#include <cmath>

namespace emlt {

GaussLegendreRule gauss_legendre(int n) {
  constexpr double kPi = 3.14159265358979323846;
  GaussLegendreRule rule{std::vector<double>(size_t(n)), std::vector<double>(size_t(n))};
  // The roots come in pairs +-z: each positive one from its classical first guess.
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = 0.0;
      for (int k = 1; k <= n; ++k) {  // P_k(z) by the three-term recurrence
        const double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p2) / k;
      }
      derivative = n * (z * p0 - p1) / (z * z - 1.0);
      const double step = p0 / derivative;
      z -= step;
      if (std::abs(step) < 1e-15) break;
    }
    const double weight = 2.0 / ((1.0 - z * z) * derivative * derivative);
    rule.x[size_t(i)] = -z;
    rule.x[size_t(n - 1 - i)] = z;
    rule.w[size_t(i)] = rule.w[size_t(n - 1 - i)] = weight;
  }
  return rule;
}

}  // namespace emlt
