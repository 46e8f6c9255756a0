#pragma once
// A blue-noise-like point set in the unit square: n points on the torus with a large
// minimum distance, randomised per estimate by a Cranley-Patterson (toroidal) shift so that
// every point is marginally uniform and estimators built on it stay unbiased.
//
// [SF] compared blue noise by optimal transport (BNOT, de Goes et al. 2012), which is far
// too expensive to build here. This set keeps what makes blue noise: no two points close
// (a Poisson-disk set by dart throwing with a slowly shrinking radius, all distances
// measured on the torus) spread evenly (then a few Lloyd steps towards a centroidal Voronoi
// tessellation of the torus, each cell's centroid estimated from a fine grid of samples).
// Because the set is periodic, a toroidal shift moves it without creating close pairs
// across the square's edges, so the shifted set is exactly as blue as the base set.
//
// The base set depends on n only (a fixed seed), is built once per n on first use and
// kept for the process's life.
#include <cstdint>
#include <vector>

#include "emlt/core/math.h"

namespace emlt {

// The unshifted set of n points (n >= 1), built on first use; thread-safe.
const std::vector<Vec2>& blue_noise_base_points(uint32_t n);

// The set shifted by `shift` (each coordinate in [0, 1)) modulo 1.
std::vector<Vec2> blue_noise_square_points(uint32_t n, const Vec2& shift);

// The smallest distance between two points of a set on the unit torus (0 for n < 2).
double min_toroidal_distance(const std::vector<Vec2>& points);

}  // namespace emlt
