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
// (2) Finding the surfaces that matter: one depth-first walk of the scene's own four-wide
// BVH (Scene::surface_bvh), a node's four children tested at once in float SIMD lanes with a
// margin that covers the rounding (a child is opened when its box meets the cone's box and
// does not lie beyond the cone's tangent plane that faces it, and its sphere meets the span)
// and taken deepest inside first; each triangle reached lowers α to θ_T if smaller, which
// shrinks the cone for the rest of the walk. A surface that meets the
// final cone lies in nodes that meet it, was reached, and so has θ_T ≥ α: the result is α*
// (clamped to [alpha_min, alpha_max]), independent of the order of the walk, hence
// deterministic. Spheres use their whole-sphere angle (a lower bound), skipped when wholly
// outside the span. The walk stops as soon as α reaches alpha_min.
//
// (Eight Embree ball queries along the segment found the same α before: each ball was at
// least an eighth of the segment wide however thin the cone, and a wide cone's balls held
// the whole room, so on the public door's 382,628 triangles the estimate was 90 % of the
// render; docs/performance.md.)
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

// The end margin, as a fraction of L.
inline constexpr double kConeEndMargin = 1e-3;

// The estimate itself (no cache). An environment vertex at either end gives alpha_max.
double estimate_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                                double alpha_min, double alpha_max);

// The same through the per-thread cache.
double cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                       double alpha_min, double alpha_max);

}  // namespace emlt::geometry_aware
