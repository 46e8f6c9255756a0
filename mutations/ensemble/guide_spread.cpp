#include "mutations/ensemble/guide_spread.h"

#include <cmath>

namespace emlt::ensemble {

double guide_spread(std::span<const Vec2> points) {
  if (points.size() < 2) return 0.0;
  double mx = 0.0, my = 0.0;
  for (const Vec2& p : points) {
    mx += double(p.x);
    my += double(p.y);
  }
  mx /= double(points.size());
  my /= double(points.size());
  double squares = 0.0;
  for (const Vec2& p : points) {
    const double dx = double(p.x) - mx, dy = double(p.y) - my;
    squares += dx * dx + dy * dy;
  }
  return std::sqrt(squares / (2.0 * double(points.size() - 1)));
}

}  // namespace emlt::ensemble
