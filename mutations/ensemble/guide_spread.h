#pragma once
// How far apart the guide paths of Υ land on the film: the spread that the ensemble-scaled
// perturbations (spread_scaled_perturbation.h) and the density jump (density_jump.h) take
// their length scales from. A function of Υ alone, never of the path being moved: Υ is
// drawn from the frozen complementary ensemble by (path type, chain, step), and the moves
// that use it keep the path type, so the forward and the reverse move of one step see the
// same scale and a symmetric kernel stays symmetric. A scale fitted to
// the moved chain's own history would not (adaptive MCMC).
#include <span>

#include "emlt/core/math.h"

namespace emlt::ensemble {

// The per-axis standard deviation of the points (pixels): sqrt(Σ |v_n - mean|² / (2 (M-1))).
// 0 for fewer than two points.
double guide_spread(std::span<const Vec2> points);

}  // namespace emlt::ensemble
