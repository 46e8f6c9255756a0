#pragma once
// Occluder-free cones around path segments, for the geometry-aware (GAMLT-like)
// perturbations (ga_perturbations.h; notes/mlt-algorithms.md §9.5, our design: the paper's
// cone estimators are not public).
//
// cone_half_angle(apex, other) gives the half-angle α of the largest cone with its apex at
// `apex` and its axis through `other` that holds no geometry other than the two endpoints'
// own surfaces (a surface whose plane passes through an endpoint: a flat wall the vertex
// lies on), over the axial span s ∈ (0, S], S = L·(1 − kConeEndMargin), L the segment's
// length (the margin keeps the far endpoint's neighbourhood, where float error decides
// what touches what, out). It is exact up to rounding, hence conservative: no surface
// meets the open cone of half-angle α within the span.
//
// Derivation. (1) Each surface's own constraint: for a triangle T, the cone of half-angle
// α misses T∩span iff α ≤ θ_T, the smallest angle from the axis over T clipped to the
// span (computed exactly: 0 if the axis meets T in the span, else the minimum over the
// clipped polygon's edges, each a closed form; cone.cpp). So α* = min over surfaces of θ_T.
// (2) Finding the surfaces that matter with bounded point queries: cut the span into
// kConeSlabs slabs [s0, s1] of length h, with p the axis point at the slab's middle. A
// point q of the cone in the slab is within h/2 of p along the axis and within s·tan α ≤
// s1·tan α of the axis, so
//     |q − p|² ≤ (h/2)² + (s1 tan α)²:
// the slab's part of the cone lies in the ball B(p, need(α)), need(α) = √((h/2)² + (s1 tan α)²).
// A point query over that ball (Scene::visit_nearby) visits every triangle that meets it;
// each visited triangle lowers α to θ_T if smaller, and the ball shrinks to the new
// need(α). A surface that meets the final cone meets some slab's final ball, was visited,
// and so has θ_T ≥ α: the result is α* (clamped to [alpha_min, alpha_max]), independent of
// the order in which Embree visits primitives, hence deterministic. Spheres use their
// whole-sphere angle (a lower bound), skipped when wholly outside the span. Cost: one point
// query per slab; the balls shrink as soon as a limiting surface is found.
//
// α = alpha_min is a floor, not a claim: a segment that grazes an edge (visible within
// float error) has a free cone narrower than that, and the perturbations' step ranges have
// their own floors anyway.
//
// What the perturbations' correctness needs is only that α is a deterministic function of
// the two endpoints (same path => same α), since the acceptance ratio uses the exact density
// of whatever step size α produces; conservativeness is what makes the step ranges mean
// "within the free cone". The estimate depends only on the endpoint positions, the scene
// and the limits, so a small per-thread cache of recent results (exact key match) returns
// bit-identical values: a path's cones are computed once when it is proposed and found
// again while it is the chain's current state.
#include "emlt/path/path.h"

namespace emlt::geometry_aware {

// The number of slabs (point queries) and the end margin, as a fraction of L.
inline constexpr int kConeSlabs = 8;
inline constexpr double kConeEndMargin = 1e-3;

// The estimate itself (no cache). An environment vertex at either end gives alpha_max.
double estimate_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                                double alpha_min, double alpha_max);

// The same through the per-thread cache.
double cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                       double alpha_min, double alpha_max);

}  // namespace emlt::geometry_aware
