#pragma once
// Spherical Fibonacci point sets (Marques et al. 2013, Swinbank-Purser offset), randomised
// so that estimators built on them stay unbiased.
//
// In the unit square the set is x_j = frac(j / golden_ratio + rotation),
// y_j = frac((j + 1/2) / N + shift). Lifted by Lambert's cylindrical equal-area map
// (phi = 2 pi x, cos(theta) = 1 - 2y on the sphere, 1 - y on the hemisphere) it is the
// spherical Fibonacci set. The random rotation alone (the papers' scrambling) leaves z
// deterministic, a midpoint rule in z with a bias of -pi/(6N^2) on cos^2; the extra
// Cranley-Patterson shift in y makes every point marginally uniform, hence unbiased.
#include <cstdint>
#include <vector>

#include "emlt/core/math.h"
#include "emlt/core/rng.h"

namespace emlt {

struct FibonacciRandomisation {
  float rotation = 0.0f;  // in [0,1): azimuthal rotation as a fraction of a turn
  float shift = 0.0f;     // in [0,1): Cranley-Patterson shift in y
  static FibonacciRandomisation draw(Rng& rng) {
    const float r = rng.uniform();
    return {r, rng.uniform()};
  }
};

// Point j of an N-point set in the unit square.
Vec2 fibonacci_square_point(uint32_t j, uint32_t n, const FibonacciRandomisation& r);
// The whole set, in order.
std::vector<Vec2> fibonacci_square_points(uint32_t n, const FibonacciRandomisation& r);
// Lambert lifts of a unit-square point: full sphere and +z hemisphere (uniform measure).
Vec3 lambert_sphere_direction(const Vec2& p);
Vec3 lambert_hemisphere_direction(const Vec2& p);

// Energy of a point set on the sphere, E_N = sqrt(4/3 - mean pairwise chord length): equals
// twice the L2 spherical cap discrepancy (Stolarsky). O(N^2).
double spherical_energy(const std::vector<Vec3>& points);

}  // namespace emlt
