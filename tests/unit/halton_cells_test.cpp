// The Halton elemental-interval cells and the error-driven refinement of Szécsi et al.
// (seed 001, section 3; sampling/halton_cells.h): the cells tile the square and each holds
// its own point, Fig. 2's worked example, exactness on constants, and that the refinement
// goes where the integrand changes.
#include "emlt/sampling/halton_cells.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "emlt/core/rng.h"

using namespace emlt;

namespace {

bool inside(const HaltonCell& cell, const std::array<double, 2>& u) {
  for (int axis = 0; axis < 2; ++axis)
    if (u[size_t(axis)] < cell.start(axis) || u[size_t(axis)] >= cell.start(axis) + cell.size(axis))
      return false;
  return true;
}

}  // namespace

// 200 refinements driven by random slopes, from random first indices: no index twice, every
// cell holds its own point (by its digits, and by coordinates), the areas sum to one, and
// each of 100 random points per run lies in exactly one cell (the design notes'
// section 5.2 check).
TEST(HaltonCells, CellsTileTheSquareAndHoldTheirOwnPoints) {
  Rng rng(3, 0);
  for (int run = 0; run < 200; ++run) {
    const uint64_t first = run < 100 ? uint64_t(run) : rng.next_u32();
    AdaptiveQuadratureOptions options;
    options.budget = 60;
    options.initial = 1 + run % 7;
    const std::vector<AdaptiveLeaf> leaves =
        refine_adaptively(first, options, [&](size_t, const std::array<double, 2>&) {
          CellSample s;
          s.value = rng.uniform();
          s.slope = {100.0 * rng.uniform(), 100.0 * rng.uniform()};
          return s;
        });
    ASSERT_EQ(leaves.size(), 60u);
    std::set<uint64_t> indices;
    double area = 0.0;
    for (const AdaptiveLeaf& leaf : leaves) {
      EXPECT_TRUE(indices.insert(leaf.cell.index).second) << leaf.cell.index;
      EXPECT_TRUE(leaf.cell.holds(leaf.cell.index));
      const std::array<double, 2> u = halton_point(leaf.cell.index);
      // On an edge (index 5: u_2 = 7/9) the coordinates may round either way: 1e-12.
      for (int axis = 0; axis < 2; ++axis) {
        EXPECT_GE(u[size_t(axis)], leaf.cell.start(axis) - 1e-12);
        EXPECT_LT(u[size_t(axis)], leaf.cell.start(axis) + leaf.cell.size(axis) + 1e-12);
      }
      area += leaf.cell.area();
    }
    EXPECT_NEAR(area, 1.0, 1e-12);
    for (int i = 0; i < 100; ++i) {
      const std::array<double, 2> u{rng.uniform(), rng.uniform()};
      int holders = 0;
      for (const AdaptiveLeaf& leaf : leaves) holders += inside(leaf.cell, u);
      EXPECT_EQ(holders, 1);
    }
  }
}

// Fig. 2: from sample 1, splitting along x adds 2; splitting 1's cell along y adds 3 and 5;
// splitting 2's cell adds 4.
TEST(HaltonCells, FigureTwoWorkedExample) {
  HaltonCell root;
  root.index = 1;
  const std::vector<HaltonCell> x = split(root, 0);
  ASSERT_EQ(x.size(), 2u);
  EXPECT_EQ(x[0].index, 1u);
  EXPECT_EQ(x[1].index, 2u);
  const std::vector<HaltonCell> y = split(x[0], 1);
  ASSERT_EQ(y.size(), 3u);
  EXPECT_EQ(y[1].index, 3u);
  EXPECT_EQ(y[2].index, 5u);
  const std::vector<HaltonCell> last = split(x[1], 0);
  EXPECT_EQ(last[1].index, 4u);
  // Index 5 sits on the edge u_2 = 7/9 of its cell [2/3, 1): integer digits place it.
  EXPECT_EQ(y[2].k[1], 2u);
  EXPECT_TRUE(y[2].holds(5));
  EXPECT_FALSE(y[1].holds(5));
}

// Eq. 3 is exact for a constant, whatever the cells; and a smooth integrand converges.
TEST(HaltonCells, ConstantsAreExactAndSmoothIntegrandsConverge) {
  const auto integrate = [](int budget, const auto& f) {
    std::vector<double> values;
    AdaptiveQuadratureOptions options;
    options.budget = budget;
    const auto leaves = refine_adaptively(17, options, [&](size_t, const std::array<double, 2>& u) {
      values.push_back(f(u));
      CellSample s;
      s.value = values.back();
      const double h = 1e-6;
      s.slope = {std::abs(f({u[0] + h, u[1]}) - f({u[0] - h, u[1]})) / (2 * h),
                 std::abs(f({u[0], u[1] + h}) - f({u[0], u[1] - h})) / (2 * h)};
      return s;
    });
    double sum = 0.0;
    for (const AdaptiveLeaf& leaf : leaves) sum += values[leaf.point] * leaf.cell.area();
    return sum;
  };
  EXPECT_NEAR(integrate(37, [](const std::array<double, 2>&) { return 2.5; }), 2.5, 1e-12);
  // int u_1^2 + sin(3 u_2) = 1/3 + (1 - cos 3) / 3.
  const auto smooth = [](const std::array<double, 2>& u) {
    return u[0] * u[0] + std::sin(3.0 * u[1]);
  };
  const double exact = 1.0 / 3.0 + (1.0 - std::cos(3.0)) / 3.0;
  const double coarse = std::abs(integrate(64, smooth) - exact);
  const double fine = std::abs(integrate(4096, smooth) - exact);
  EXPECT_LT(fine, 1e-3);  // measured 3.6e-4: Eq. 3 is a first-order rule
  EXPECT_LT(fine, coarse / 8.0);
}

// A narrow bump at c on a flat floor: with the error estimate deciding, far more points go
// near the bump than its share of the square (what Eq. 4 asks for: equal variation per
// cell), and the bump's integral comes out better than with equal cells.
TEST(HaltonCells, RefinementGoesWhereTheIntegrandChanges) {
  const std::array<double, 2> c{0.71, 0.23};
  const double width = 0.03;
  const auto f = [&](const std::array<double, 2>& u) {
    const double r2 = (u[0] - c[0]) * (u[0] - c[0]) + (u[1] - c[1]) * (u[1] - c[1]);
    return 1.0 + 200.0 * std::exp(-r2 / (width * width));
  };
  const double exact_bump = 200.0 * 3.14159265358979323846 * width * width;  // (all but e^-300)
  const auto run = [&](int initial, int* near) {
    std::vector<double> values;
    AdaptiveQuadratureOptions options;
    options.budget = 400;
    options.initial = initial;
    const auto leaves = refine_adaptively(5, options, [&](size_t, const std::array<double, 2>& u) {
      values.push_back(f(u));
      CellSample s;
      s.value = values.back();
      const double h = 1e-6;
      s.slope = {std::abs(f({u[0] + h, u[1]}) - f({u[0] - h, u[1]})) / (2 * h),
                 std::abs(f({u[0], u[1] + h}) - f({u[0], u[1] - h})) / (2 * h)};
      return s;
    });
    *near = 0;
    double sum = 0.0;
    for (const AdaptiveLeaf& leaf : leaves) {
      const std::array<double, 2> u = halton_point(leaf.cell.index);
      *near += std::hypot(u[0] - c[0], u[1] - c[1]) < 3.0 * width;
      sum += values[leaf.point] * leaf.cell.area();
    }
    return std::abs(sum - 1.0 - exact_bump);
  };
  int near_adaptive = 0, near_uniform = 0;
  const double adaptive_error = run(1, &near_adaptive);
  const double uniform_error = run(400, &near_uniform);  // equal cells only
  // The disc of radius 3 w is 2.5 % of the square: 10 of 400 equal cells' points.
  EXPECT_LT(near_uniform, 20);
  EXPECT_GT(near_adaptive, 4 * near_uniform);
  EXPECT_LT(adaptive_error, uniform_error / 4.0);
}
