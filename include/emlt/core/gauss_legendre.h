#pragma once
// The n-point Gauss–Legendre rule on [-1, 1]: nodes in increasing order and their weights
// (summing to 2), exact for polynomials of degree 2n - 1. Computed by Newton's method on
// P_n; the quadratures of the BSDF tables and the spherical-Gaussian integrals share it.
#include <vector>

namespace emlt {

struct GaussLegendreRule {
  std::vector<double> x, w;
};

GaussLegendreRule gauss_legendre(int n);

}  // namespace emlt
