#include "emlt/mcmc/adaptive_alpha.h"

#include <algorithm>
#include <cmath>

namespace emlt::ensemble {

double image_coverage(std::span<const Vec2> raster, int width, int height) {
  if (raster.size() < 2 || width <= 0 || height <= 0) return 0.0;
  Vec2 lo = raster[0], hi = raster[0];
  for (const Vec2& p : raster) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double area = double(hi.x - lo.x) * double(hi.y - lo.y);
  return std::clamp(area / (double(width) * double(height)), 0.0, 1.0);
}

double adaptive_alpha(double coverage, const AdaptiveAlphaParams& p) {
  const double w = 1.0 / (1.0 + std::exp(-(coverage - p.centre) / p.sigma_squared));
  return (1.0 - w) * p.alpha_large + w * p.alpha_small;
}

}  // namespace emlt::ensemble
