#pragma once
// A lower bound on the distance from any point to the scene's nearest surface, on a coarse
// voxel grid, for the geometry-aware cone's cheap bound (mutations/geometry_aware/cone.h,
// `--gamlt-cone field`): a few lookups along a segment replace most of the hierarchy walk
// that finds the exact cone.
//
// Built once per scene from the surface hierarchy's triangles and spheres: a cell is
// occupied when a surface may pass through it (a triangle's plane within half a cell
// diagonal of the cell's centre, inside the triangle's box; a sphere's shell within half a
// diagonal), over-marking only, never under. A separable exact Euclidean distance transform
// then gives each cell the distance D from its centre to the nearest occupied cell's centre.
// Any surface point lies within half a diagonal h√3/2 of an occupied centre, so the cell's
// centre is at least (D − √3/2) h from every surface, and a point p of the cell at least
// that minus |p − centre| (the distance to the surfaces is 1-Lipschitz). Points outside the
// grid (which holds every surface with a cell to spare) are bounded through their
// projection onto it: projecting onto a convex box never brings a point nearer anything
// inside.
//
// What "lower bound" buys: a segment's cone checked with these clearances is never wider
// than its true occluder-free cone. What it costs: the bound is up to about 1.7 cells below
// the truth, so cones near surfaces come out narrower than the exact ones.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "emlt/core/math.h"

namespace emlt {

class SurfaceBvh;

class ClearanceField {
 public:
  // Cells along the grid's longest side: 128 keeps the grid at most 8 MB.
  static constexpr int kResolution = 128;

  void build(const SurfaceBvh& surfaces, int resolution = kResolution);

  // A lower bound (≥ 0) on the distance from p to the nearest surface. A grid without
  // surfaces gives +∞.
  double lower_bound(const DVec3& p) const {
    if (values_.empty()) return std::numeric_limits<double>::infinity();
    const DVec3 inside = glm::clamp(p, lower_, upper_);
    const DVec3 cell = (inside - lower_) * inverse_cell_;
    int i[3];
    for (int a = 0; a < 3; ++a) i[a] = std::min(std::max(int(cell[a]), 0), size_[a] - 1);
    const DVec3 centre = lower_ + (DVec3(i[0], i[1], i[2]) + 0.5) * cell_size_;
    const double within =
        double(values_[(size_t(i[2]) * size_t(size_[1]) + size_t(i[1])) * size_t(size_[0]) +
                       size_t(i[0])]) -
        glm::length(inside - centre);
    const double outside = glm::length(p - inside);
    if (outside == 0.0) return std::max(0.0, within);
    return within > 0.0 ? std::sqrt(within * within + outside * outside) : outside;
  }

  double cell_size() const { return cell_size_; }
  int size(int axis) const { return size_[axis]; }

 private:
  DVec3 lower_{0.0}, upper_{0.0};
  double cell_size_ = 1.0, inverse_cell_ = 1.0;
  int size_[3] = {0, 0, 0};
  // Per cell (x fastest), (D − √3/2) h rounded down, or −∞-like for occupied cells.
  std::vector<float> values_;
};

}  // namespace emlt
