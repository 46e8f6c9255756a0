#pragma once
// Occluder-free cones around path segments, for the geometry-aware (GAMLT-like)
// perturbations (ga_perturbations.h; notes/mlt-algorithms.md §9.5, our design: the paper's
// cone estimators are not public).
//
// cone_half_angle(apex, other) estimates the half-angle α of the largest cone with its apex
// at `apex` and its axis through `other` that holds no geometry other than the two
// endpoints' own surfaces. Method: Embree point queries (Scene::clearance) at the probe
// points s = t·L along the segment (t = 1/4, 1/2, 3/4; L its length), skipping surfaces
// that pass through either endpoint (a flat wall the vertex lies on never blocks the
// segment's interior). With clearance r at distance s from the apex, the ball B(p, r) is
// free, so the cone of half-angle atan(r/s), whose cross-section there is the disk of
// radius s·tan α ≤ r, is free at that probe; α
// is the minimum over the probes, clamped to [alpha_min, alpha_max].
//
// It is an approximation: free space is verified at the probe points only (an occluder
// between probes, or very near an endpoint, can lie inside the returned cone). What the
// perturbations' correctness needs is only that α is a deterministic function of the two
// endpoints (same path => same α), since the acceptance ratio uses the exact density of
// whatever step size α produces. The estimate depends only on the endpoint positions, the
// scene and the limits, so a small per-thread cache of recent results (exact key match)
// returns bit-identical values: a path's cones are computed once when it is proposed and
// found again while it is the chain's current state.
#include "emlt/path/path.h"

namespace emlt::geometry_aware {

// Probe points along the segment, as fractions of its length.
inline constexpr double kConeProbes[] = {0.25, 0.5, 0.75};

// The estimate itself (no cache). An environment vertex at either end gives alpha_max.
double estimate_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                                double alpha_min, double alpha_max);

// The same through the per-thread cache.
double cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                       double alpha_min, double alpha_max);

}  // namespace emlt::geometry_aware
