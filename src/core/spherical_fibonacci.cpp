#include "emlt/core/spherical_fibonacci.h"

namespace emlt {

namespace {
// 1/golden ratio in double: j can be large, and float loses the fractional part.
constexpr double kInverseGoldenRatio = 0.61803398874989484820;

float fractional(double x) { return static_cast<float>(x - std::floor(x)); }
}  // namespace

Vec2 fibonacci_square_point(uint32_t j, uint32_t n, const FibonacciRandomisation& r) {
  const float x = fractional(double(j) * kInverseGoldenRatio + double(r.rotation));
  const float y = fractional((double(j) + 0.5) / double(n) + double(r.shift));
  return {glm::min(x, kOneMinusEpsilon), glm::min(y, kOneMinusEpsilon)};
}

std::vector<Vec2> fibonacci_square_points(uint32_t n, const FibonacciRandomisation& r) {
  std::vector<Vec2> points(n);
  for (uint32_t j = 0; j < n; ++j) points[j] = fibonacci_square_point(j, n, r);
  return points;
}

Vec3 lambert_sphere_direction(const Vec2& p) {
  const float z = 1.0f - 2.0f * p.y;
  const float r = safe_sqrt(1.0f - z * z), phi = kTwoPi * p.x;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 lambert_hemisphere_direction(const Vec2& p) {
  const float z = 1.0f - p.y;
  const float r = safe_sqrt(1.0f - z * z), phi = kTwoPi * p.x;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

double spherical_energy(const std::vector<Vec3>& points) {
  const size_t n = points.size();
  double sum = 0.0;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) sum += 2.0 * double(glm::length(points[i] - points[j]));
  return std::sqrt(glm::max(4.0 / 3.0 - sum / (double(n) * double(n)), 0.0));
}

}  // namespace emlt
