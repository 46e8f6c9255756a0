#pragma once
// Szécsi, Szirmay-Kalos, Kurt and Csébfalvi's adaptive quadrature over the unit square
// (seed 001, section 3). The square is cut into the elemental intervals of the (2, 3) Halton
// sequence, each holding exactly one of its points (section 3.2, Fig. 2); the integral is
// the sum of each point's value times its cell's area (Eq. 3). Each cell carries the error
// that splitting it along one axis would remove, |dF/du_d| Delta_d / 2 * Delta (Eq. 4); the
// (cell, axis) of largest error is split next, and the new cells' points are the Halton
// points that fall into them, index i + k B_1^R_1 B_2^R_2.
//
// The result is deterministic given the first index and the integrand: the partition depends
// on the values found, so it is a consistent but biased estimate (the paper: "the term
// unbiasedness is not applicable").
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace emlt {

inline constexpr uint32_t kHaltonBases[2] = {2, 3};

// The radical inverse of `index` in `base`: the Halton sequence's coordinate.
double radical_inverse(uint64_t index, uint32_t base);

// The Halton point of `index`: (radical_inverse(index, 2), radical_inverse(index, 3)).
std::array<double, 2> halton_point(uint64_t index);

// An elemental interval [k_1 2^-R_1, (k_1 + 1) 2^-R_1) x [k_2 3^-R_2, (k_2 + 1) 3^-R_2) and the
// index of the one Halton point it holds. The coordinates are integers, so a point on a
// cell's edge (index 5: u_2 = 7/9) is never misfiled by rounding.
struct HaltonCell {
  uint64_t index = 0;
  std::array<uint32_t, 2> level{0, 0};  // R_1, R_2
  std::array<uint64_t, 2> k{0, 0};

  double size(int axis) const;  // B_d^-R_d
  double area() const { return size(0) * size(1); }
  // Where the cell starts along `axis` (k_d B_d^-R_d).
  double start(int axis) const { return double(k[size_t(axis)]) * size(axis); }
  // Whether the cell holds the Halton point of `point_index`, by its base-B digits.
  bool holds(uint64_t point_index) const;
};

// Whether `cell` can be split along `axis`: its edge there stays above 2^-30 (beyond float
// directions' resolution), which also keeps every new index within 64 bits.
bool can_split(const HaltonCell& cell, int axis);

// The B_d cells `cell` splits into along `axis`. The first keeps the cell's own point; the
// others hold the points index + k B_1^R_1 B_2^R_2, k = 1 .. B_d - 1 (section 3.2; the
// printed list drops "i +" from its last term).
std::vector<HaltonCell> split(const HaltonCell& cell, int axis);

// What the refinement needs to know of the integrand at one point: a scalar size of F (for
// colour, its luminance) and |dF/du_d| there.
struct CellSample {
  double value = 0.0;
  std::array<double, 2> slope{0.0, 0.0};
};

struct AdaptiveQuadratureOptions {
  int budget = 1;   // points in all
  int initial = 1;  // points placed by splitting the largest cells before the errors decide
  // Section 3.3: "a positive constant is added to the derivative ... reduced as the size of
  // the subdomain gets smaller". The paper gives no value; here it is c times the mean |F|
  // of the points so far times the cell's edge, as if F changed by c times its mean across
  // a whole edge of the square, so that no cell is left unsplit forever where F' = 0.
  double robustness = 1.0;
};

// One cell of the final partition and the point it holds (the order `evaluate` saw it).
struct AdaptiveLeaf {
  HaltonCell cell;
  size_t point = 0;
};

// Refines from the whole square, whose point is the Halton point of `first_index`, until
// `options.budget` points are placed; `evaluate(point, u)` is called once per point, in the
// order the points are made (point 0 first). Returns the leaves, one per point; the
// integral is sum over leaves of F(point) * cell.area().
std::vector<AdaptiveLeaf> refine_adaptively(
    uint64_t first_index, const AdaptiveQuadratureOptions& options,
    const std::function<CellSample(size_t point, const std::array<double, 2>& u)>& evaluate);

}  // namespace emlt
