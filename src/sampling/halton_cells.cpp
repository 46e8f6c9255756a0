#include "emlt/sampling/halton_cells.h"

#include <algorithm>
#include <queue>

namespace emlt {

namespace {

uint64_t power(uint64_t base, uint32_t exponent) {
  uint64_t p = 1;
  for (uint32_t i = 0; i < exponent; ++i) p *= base;
  return p;
}

// The smallest edge a split may make along an axis: below float directions' resolution
// nothing is gained, and 2^30 3^19 keeps every index a split makes within 64 bits.
constexpr double kSmallestEdge = 0x1p-30;

}  // namespace

double radical_inverse(uint64_t index, uint32_t base) {
  const double inverse = 1.0 / double(base);
  double scale = inverse, result = 0.0;
  while (index > 0) {
    result += double(index % base) * scale;
    index /= base;
    scale *= inverse;
  }
  return result;
}

std::array<double, 2> halton_point(uint64_t index) {
  return {radical_inverse(index, kHaltonBases[0]), radical_inverse(index, kHaltonBases[1])};
}

double HaltonCell::size(int axis) const {
  return 1.0 / double(power(kHaltonBases[axis], level[size_t(axis)]));
}

bool HaltonCell::holds(uint64_t point_index) const {
  for (int axis = 0; axis < 2; ++axis) {
    // The point's first R_d digits, most significant first, are the cell's k_d.
    const uint32_t base = kHaltonBases[axis];
    uint64_t rest = point_index, cell = 0;
    for (uint32_t m = 0; m < level[size_t(axis)]; ++m) {
      cell = cell * base + rest % base;
      rest /= base;
    }
    if (cell != k[size_t(axis)]) return false;
  }
  return true;
}

bool can_split(const HaltonCell& cell, int axis) {
  return cell.size(axis) / double(kHaltonBases[axis]) >= kSmallestEdge;
}

std::vector<HaltonCell> split(const HaltonCell& cell, int axis) {
  const uint32_t base = kHaltonBases[axis];
  const uint64_t stride = power(2, cell.level[0]) * power(3, cell.level[1]);
  const uint64_t digit_place = power(base, cell.level[size_t(axis)]);
  std::vector<HaltonCell> children(base, cell);
  for (uint32_t k = 0; k < base; ++k) {
    HaltonCell& child = children[k];
    child.index = cell.index + k * stride;
    // Adding k B_1^R_1 B_2^R_2 keeps the index's first R_1 binary and R_2 ternary digits, so
    // the child stays in the cell; its next digit along `axis` says which part it is in.
    child.level[size_t(axis)] = cell.level[size_t(axis)] + 1;
    child.k[size_t(axis)] = cell.k[size_t(axis)] * base + (child.index / digit_place) % base;
  }
  return children;
}

std::vector<AdaptiveLeaf> refine_adaptively(
    uint64_t first_index, const AdaptiveQuadratureOptions& options,
    const std::function<CellSample(size_t point, const std::array<double, 2>& u)>& evaluate) {
  const size_t budget = size_t(std::max(options.budget, 1));
  std::vector<AdaptiveLeaf> leaves;
  std::vector<CellSample> samples;
  leaves.reserve(budget);
  samples.reserve(budget);
  double sum_abs = 0.0;  // of the points' values, for the robustness term
  const auto add_point = [&](const HaltonCell& cell) {
    const size_t point = samples.size();
    samples.push_back(evaluate(point, halton_point(cell.index)));
    sum_abs += std::abs(samples.back().value);
    leaves.push_back(AdaptiveLeaf{cell, point});
  };
  // Splits leaf `leaf` along `axis`: it keeps its point in the first part, and the others get
  // theirs. Returns the leaves now covering the old cell.
  const auto split_leaf = [&](size_t leaf, int axis) {
    const std::vector<HaltonCell> parts = split(leaves[leaf].cell, axis);
    std::vector<size_t> covering{leaf};
    leaves[leaf].cell = parts[0];
    for (size_t k = 1; k < parts.size(); ++k) {
      covering.push_back(leaves.size());
      add_point(parts[k]);
    }
    return covering;
  };
  const auto points_for = [](int axis) { return size_t(kHaltonBases[axis] - 1); };

  HaltonCell root;
  root.index = first_index;
  add_point(root);

  // The uniform start: the largest cell split across its longer edge (the first axis on a
  // tie), until `initial` points are placed.
  const size_t initial = std::min(size_t(std::max(options.initial, 1)), budget);
  while (leaves.size() < initial) {
    size_t largest = 0;
    for (size_t i = 1; i < leaves.size(); ++i)
      if (leaves[i].cell.area() > leaves[largest].cell.area()) largest = i;
    const HaltonCell& cell = leaves[largest].cell;
    int axis = cell.size(1) > cell.size(0) ? 1 : 0;
    if (leaves.size() + points_for(axis) > initial) axis = 0;
    if (!can_split(cell, axis)) break;
    split_leaf(largest, axis);
  }

  // Each (leaf, axis) with the error a split would remove (Eq. 4 with section 3.3's term);
  // on equal errors (an integrand flat so far) the larger cell first. A leaf's entries
  // go stale when it is split: they carry its levels at the time.
  struct Candidate {
    double error, area;
    size_t leaf;
    int axis;
    std::array<uint32_t, 2> level;
    bool operator<(const Candidate& o) const {
      return error != o.error ? error < o.error : area < o.area;
    }
  };
  std::priority_queue<Candidate> candidates;
  // The robustness term scales with the points' mean |F|, which moves as points are added;
  // the candidates are recomputed whenever it has moved by more than a factor of 2 since
  // they were, so that a cell offered while the mean was still 0 (every point so far dark)
  // is not left with no error for ever.
  double scale = 0.0;
  const auto offer = [&](size_t leaf) {
    const HaltonCell& cell = leaves[leaf].cell;
    const CellSample& s = samples[leaves[leaf].point];
    const double mean_abs = scale;
    for (int axis = 0; axis < 2; ++axis) {
      if (!can_split(cell, axis)) continue;
      const double edge = cell.size(axis);
      const double slope = s.slope[size_t(axis)] + options.robustness * mean_abs * edge;
      candidates.push(
          Candidate{slope * edge / 2.0 * cell.area(), cell.area(), leaf, axis, cell.level});
    }
  };
  const auto offer_all = [&] {
    scale = sum_abs / double(samples.size());
    candidates = {};
    for (size_t i = 0; i < leaves.size(); ++i) offer(i);
  };
  offer_all();
  while (leaves.size() < budget && !candidates.empty()) {
    const double mean_abs = sum_abs / double(samples.size());
    if (options.robustness > 0.0 && (mean_abs > 2.0 * scale || mean_abs < 0.5 * scale)) {
      offer_all();
      continue;
    }
    const Candidate c = candidates.top();
    candidates.pop();
    if (c.level != leaves[c.leaf].cell.level) continue;  // split since
    // An axis-2 split adds two points; with one left only an axis-1 split fits.
    if (leaves.size() + points_for(c.axis) > budget) continue;
    for (const size_t leaf : split_leaf(c.leaf, c.axis)) offer(leaf);
  }
  return leaves;
}

}  // namespace emlt
