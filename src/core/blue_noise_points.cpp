#include "emlt/core/blue_noise_points.h"

#include <cmath>
#include <map>
#include <memory>
#include <mutex>

#include "emlt/core/rng.h"

namespace emlt {

namespace {

using DVec2 = glm::dvec2;

double wrap(double v) {
  return v - std::floor(v);
}
// The shortest signed difference between two coordinates on the unit circle.
double toroidal_delta(double a, double b) {
  const double d = a - b;
  return d - std::round(d);
}
double toroidal_distance2(const DVec2& a, const DVec2& b) {
  const double dx = toroidal_delta(a.x, b.x), dy = toroidal_delta(a.y, b.y);
  return dx * dx + dy * dy;
}

// Points bucketed in a g x g grid over the torus, for nearest-point queries.
class TorusGrid {
 public:
  explicit TorusGrid(int g) : g_(g), cells_(size_t(g) * size_t(g)) {}
  void add(const DVec2& p, int index) { cells_[cell(p)].push_back(index); }
  // Index of the point of `points` nearest to q (-1 when the grid is empty), with its squared
  // distance. Rings of cells are scanned outwards until no closer point can be further out.
  int nearest(const std::vector<DVec2>& points, const DVec2& q, double* distance2) const {
    const int cx = std::min(int(q.x * g_), g_ - 1), cy = std::min(int(q.y * g_), g_ - 1);
    int best = -1;
    double best2 = 1e300;
    for (int ring = 0; ring <= g_ / 2 + 1; ++ring) {
      // Every point in ring r + 1 or beyond lies at least r cells away.
      if (best >= 0 && best2 < (double(ring - 1) / g_) * (double(ring - 1) / g_) && ring > 0) break;
      for (int dy = -ring; dy <= ring; ++dy)
        for (int dx = -ring; dx <= ring; ++dx) {
          if (std::max(std::abs(dx), std::abs(dy)) != ring) continue;
          // Small grids: the same cell can be reached twice around the torus; harmless.
          const int x = ((cx + dx) % g_ + g_) % g_, y = ((cy + dy) % g_ + g_) % g_;
          for (int index : cells_[size_t(y) * g_ + x]) {
            const double d2 = toroidal_distance2(points[size_t(index)], q);
            if (d2 < best2) best2 = d2, best = index;
          }
        }
    }
    *distance2 = best2;
    return best;
  }

 private:
  size_t cell(const DVec2& p) const {
    const int x = std::min(int(p.x * g_), g_ - 1), y = std::min(int(p.y * g_), g_ - 1);
    return size_t(y) * size_t(g_) + size_t(x);
  }
  int g_;
  std::vector<std::vector<int>> cells_;
};

int grid_size(uint32_t n) {
  return std::max(1, int(std::sqrt(double(n))));
}

std::vector<DVec2> dart_throwing(uint32_t n, Rng& rng) {
  // Start near the densest packing's spacing (hexagonal: sqrt(2 / (sqrt 3 n))) and shrink
  // the radius whenever many darts in a row miss, until n points fit.
  double radius = 0.9 * std::sqrt(2.0 / (std::sqrt(3.0) * n));
  std::vector<DVec2> points;
  points.reserve(n);
  TorusGrid grid(grid_size(n));
  int misses = 0;
  while (points.size() < n) {
    const DVec2 p(rng.uniform_double(), rng.uniform_double());
    double d2 = 1e300;
    if (!points.empty()) grid.nearest(points, p, &d2);
    if (d2 >= radius * radius) {
      grid.add(p, int(points.size()));
      points.push_back(p);
      misses = 0;
    } else if (++misses > 200) {
      radius *= 0.98;
      misses = 0;
    }
  }
  return points;
}

void lloyd_step(std::vector<DVec2>& points) {
  const uint32_t n = uint32_t(points.size());
  TorusGrid grid(grid_size(n));
  for (uint32_t i = 0; i < n; ++i) grid.add(points[i], int(i));
  // About 64 grid samples per cell estimate each Voronoi cell's centroid.
  const int side = std::max(16, int(std::ceil(8.0 * std::sqrt(double(n)))));
  std::vector<DVec2> offset(n, DVec2(0.0));
  std::vector<int> count(n, 0);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const DVec2 q((x + 0.5) / side, (y + 0.5) / side);
      double d2;
      const int i = grid.nearest(points, q, &d2);
      offset[size_t(i)] +=
          DVec2(toroidal_delta(q.x, points[size_t(i)].x), toroidal_delta(q.y, points[size_t(i)].y));
      ++count[size_t(i)];
    }
  for (uint32_t i = 0; i < n; ++i)
    if (count[i] > 0) {
      const DVec2 c = points[i] + offset[i] / double(count[i]);
      points[i] = DVec2(wrap(c.x), wrap(c.y));
    }
}

std::vector<Vec2> build(uint32_t n) {
  Rng rng(0xb10e, n);
  std::vector<DVec2> points = dart_throwing(n, rng);
  // A few steps only: they spread the points evenly, while many would drift towards a
  // regular lattice, whose spectrum has peaks instead of blue noise's flat tail.
  for (int step = 0; step < 4; ++step) lloyd_step(points);
  std::vector<Vec2> out(n);
  for (uint32_t i = 0; i < n; ++i)
    out[i] = {glm::min(float(points[i].x), kOneMinusEpsilon),
              glm::min(float(points[i].y), kOneMinusEpsilon)};
  return out;
}

}  // namespace

const std::vector<Vec2>& blue_noise_base_points(uint32_t n) {
  // The last set each thread used, so that a render's shading points do not contend for
  // the lock; sets are never freed, so the reference stays valid.
  thread_local uint32_t last_n = 0;
  thread_local const std::vector<Vec2>* last = nullptr;
  if (last && last_n == n) return *last;
  static std::mutex mutex;
  static std::map<uint32_t, std::unique_ptr<const std::vector<Vec2>>> sets;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = sets[n];
  if (!slot) slot = std::make_unique<const std::vector<Vec2>>(build(std::max(n, 1u)));
  last_n = n;
  last = slot.get();
  return *last;
}

std::vector<Vec2> blue_noise_square_points(uint32_t n, const Vec2& shift) {
  const std::vector<Vec2>& base = blue_noise_base_points(n);
  std::vector<Vec2> points(base.size());
  for (size_t i = 0; i < base.size(); ++i) {
    const double x = wrap(double(base[i].x) + shift.x), y = wrap(double(base[i].y) + shift.y);
    points[i] = {glm::min(float(x), kOneMinusEpsilon), glm::min(float(y), kOneMinusEpsilon)};
  }
  return points;
}

double min_toroidal_distance(const std::vector<Vec2>& points) {
  if (points.size() < 2) return 0.0;
  std::vector<DVec2> p;
  for (const Vec2& q : points) p.emplace_back(q.x, q.y);
  TorusGrid grid(grid_size(uint32_t(p.size())));
  double best2 = 1e300;
  for (size_t i = 0; i < p.size(); ++i) {
    double d2;
    if (i > 0 && grid.nearest(p, p[i], &d2) >= 0) best2 = std::min(best2, d2);
    grid.add(p[i], int(i));
  }
  return std::sqrt(best2);
}

}  // namespace emlt
