#include "emlt/scene/clearance_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "emlt/scene/surface_bvh.h"

namespace emlt {

namespace {

// The squared distance from each index to the nearest index whose input is 0 (inputs are 0 or
// +∞ on the first pass, squared distances on the later ones), along one line of n values
// (Felzenszwalb and Huttenlocher's lower envelope of parabolas; `v`, `z` and `out` scratch).
void distance_transform_1d(const double* f, int n, double* out, int* v, double* z) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] == kInfinity) continue;
    // The parabola rooted at q replaces those it lies below from their intersection on.
    while (k >= 0) {
      const double s =
          ((f[q] + double(q) * q) - (f[v[k]] + double(v[k]) * v[k])) / (2.0 * (q - v[k]));
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInfinity
                  : ((f[q] + double(q) * q) - (f[v[k - 1]] + double(v[k - 1]) * v[k - 1])) /
                        (2.0 * (q - v[k - 1]));
  }
  if (k < 0) {
    std::fill(out, out + n, kInfinity);
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (j < k && z[j + 1] < double(q)) ++j;
    out[q] = (q - v[j]) * double(q - v[j]) + f[v[j]];
  }
}

}  // namespace

void ClearanceField::build(const SurfaceBvh& surfaces, int resolution) {
  values_.clear();
  const uint32_t triangles = surfaces.triangle_count();
  if (triangles == 0 && surfaces.spheres().empty()) return;
  DVec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (uint32_t t = 0; t < triangles; ++t) {
    const SurfaceBvh::Corners c = surfaces.corners(t);
    for (const Vec3* p : {&c.a, &c.b, &c.c})
      lo = glm::min(lo, DVec3(*p)), hi = glm::max(hi, DVec3(*p));
  }
  for (const SurfaceBvh::Sphere& s : surfaces.spheres()) {
    lo = glm::min(lo, DVec3(s.center) - double(s.radius));
    hi = glm::max(hi, DVec3(s.center) + double(s.radius));
  }
  const DVec3 extent = hi - lo;
  cell_size_ = std::max({extent.x, extent.y, extent.z, 1e-6}) / double(resolution);
  inverse_cell_ = 1.0 / cell_size_;
  // A cell to spare on every side: the grid's box then holds every surface strictly inside
  // (lower_bound's projection for points outside it).
  for (int a = 0; a < 3; ++a) size_[a] = int(std::ceil(extent[a] * inverse_cell_)) + 3;
  lower_ = lo - cell_size_;
  upper_ = lower_ + DVec3(size_[0], size_[1], size_[2]) * cell_size_;
  const size_t nx = size_t(size_[0]), ny = size_t(size_[1]), nz = size_t(size_[2]);
  const size_t cells = nx * ny * nz;
  const auto index = [&](int x, int y, int z) {
    return (size_t(z) * ny + size_t(y)) * nx + size_t(x);
  };
  const double half_diagonal = 0.5 * std::sqrt(3.0) * cell_size_;
  // Cell ranges are widened by one and the tests by a relative slack: over-marking is safe.
  const double slack = 1e-6 * (cell_size_ + glm::length(glm::abs(lo) + glm::abs(hi)));
  const auto cell_range = [&](const DVec3& a, const DVec3& b, int* first, int* last) {
    for (int k = 0; k < 3; ++k) {
      first[k] = std::max(0, int(std::floor((a[k] - lower_[k]) * inverse_cell_)) - 1);
      last[k] = std::min(size_[k] - 1, int(std::floor((b[k] - lower_[k]) * inverse_cell_)) + 1);
    }
  };
  const auto centre = [&](int x, int y, int z) {
    return lower_ + (DVec3(x, y, z) + 0.5) * cell_size_;
  };
  std::vector<double> grid(cells, std::numeric_limits<double>::infinity());
  for (uint32_t t = 0; t < triangles; ++t) {
    const SurfaceBvh::Corners c = surfaces.corners(t);
    const DVec3 a(c.a), b(c.b), d(c.c);
    int first[3], last[3];
    cell_range(glm::min(a, glm::min(b, d)), glm::max(a, glm::max(b, d)), first, last);
    DVec3 n = glm::cross(b - a, d - a);
    const double n_length = glm::length(n);
    // A degenerate triangle marks its whole box.
    n = n_length > 0.0 ? n / n_length : DVec3(0.0);
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int x = first[0]; x <= last[0]; ++x)
          if (std::abs(glm::dot(n, centre(x, y, z) - a)) <= half_diagonal + slack)
            grid[index(x, y, z)] = 0.0;
  }
  for (const SurfaceBvh::Sphere& s : surfaces.spheres()) {
    const DVec3 o(s.center);
    const double r = double(s.radius);
    int first[3], last[3];
    cell_range(o - r, o + r, first, last);
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int x = first[0]; x <= last[0]; ++x)
          if (std::abs(glm::length(centre(x, y, z) - o) - r) <= half_diagonal + slack)
            grid[index(x, y, z)] = 0.0;
  }
  // The squared distance transform, one axis at a time.
  const size_t longest = std::max({nx, ny, nz});
  std::vector<double> line(longest), out(longest), z(longest + 1);
  std::vector<int> v(longest);
  for (int axis = 0; axis < 3; ++axis) {
    const size_t n = size_t(size_[axis]);
    const size_t stride = axis == 0 ? 1 : axis == 1 ? nx : nx * ny;
    // The lines along the axis start at the cells whose coordinate along it is 0: the other
    // two coordinates' grid, a (outer) and b (inner).
    const size_t count_a = axis == 2 ? ny : nz, count_b = axis == 0 ? ny : nx;
    const size_t step_a = axis == 2 ? nx : nx * ny, step_b = axis == 0 ? nx : 1;
    for (size_t ia = 0; ia < count_a; ++ia)
      for (size_t ib = 0; ib < count_b; ++ib) {
        const size_t start = ia * step_a + ib * step_b;
        for (size_t i = 0; i < n; ++i) line[i] = grid[start + i * stride];
        distance_transform_1d(line.data(), int(n), out.data(), v.data(), z.data());
        for (size_t i = 0; i < n; ++i) grid[start + i * stride] = out[i];
      }
  }
  values_.resize(cells);
  for (size_t i = 0; i < cells; ++i) {
    const double bound = (std::sqrt(grid[i]) - 0.5 * std::sqrt(3.0)) * cell_size_ - slack;
    // Rounded down to float, so that the stored value stays a lower bound.
    float f = float(bound);
    if (double(f) > bound) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    values_[i] = f;
  }
}

}  // namespace emlt
