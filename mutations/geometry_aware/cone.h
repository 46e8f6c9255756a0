#pragma once
// Occluder-free cones around path segments, for the geometry-aware (GAMLT-like)
// perturbations (ga_perturbations.h; our design: the paper's
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
// outside the span. The walk stops as soon as α reaches alpha_min. Before it, one candidate
// is tested: the triangle that limited this thread's last cone from the same apex (the lens
// and caustic moves keep one end of the segment they move, so y's cone is often limited by
// what limited x's); it narrows the cone the walk starts from, or ends the estimate at the
// floor, and by the argument above cannot change the result (docs/performance.md: the
// textured door's estimates 34 % fewer instructions).
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
//
// The cheap bound (ConeMethod::Field, `--gamlt-cone field`).
// The exact walk costs about 6,000 instructions per mutation on the Cornell box, more than a
// whole MLT mutation, and 18,000 on the public door (docs/performance.md). The field bound
// trades width for time: field_cone_half_angle is never wider than the exact cone (same
// span, same own-surface rule at the ends). Over the middle of the segment, s ∈ [s_a, s_b]
// with s_a = f L and s_b = S − f L (f = kFieldEndFraction), it reads lower bounds c(s) on the
// distance from the axis point at s to any surface (Scene::clearance_field, a coarse voxel
// distance transform). The cone's disc at σ (radius σ tan α) lies in the ball of radius
// c(σ) about its centre when c(σ) ≥ σ tan α, and the distance is 1-Lipschitz, so one sample
// at s covers every σ ∈ [s, (c(s) + s)/(1 + tan α)]. The march starts at s_a with tan α =
// tan alpha_max and steps by what each sample covers; where a sample covers less than a
// quarter of its clearance (kFieldLeastStep) it lowers tan α until that is covered:
// (c − m)/(s + m) for the step m = c/4 (about 3/4 of c/s). Lowering α never uncovers what
// earlier samples covered, so the whole middle is free at the final α; after
// kFieldMaxLowerings lowerings or kFieldMaxSamples samples it gives the floor. The two ends,
// [0, s_a] and [s_b, S], go to the exact walk over just those spans, starting from the
// field's α, since the field cannot tell the endpoints' own surfaces from the rest. The
// result is the smallest of the three, each conservative; it is a deterministic function of
// the endpoints, which is all the perturbations' correctness needs.
//
// Measured (docs/performance.md, "A cheap conservative cone"): far narrower than the exact
// cone (the Cornell box's cones at the floor 7 % → 53 %, Veach Ajar's 19 % → 95 %), because
// even in the middle the field sees the endpoints' own walls (a cone wider than the grazing
// angle is never certified) and its error, up to 1.7 cells, is of the order of the thin
// cones' radii; faster than the exact walk on the large scenes only because of those floors,
// slower on the small ones. Hence a flag, not the default.
//
// The memoised cones (ConeMethod::Cells, `--gamlt-cone cells`, the default; cone_cells.h)
// keep the exact walk but run it for a quantised segment, the key of a per-thread table shared
// by nearby states; estimate_cone_tan gives them the walk's own result, which tells an exact
// cone from one at a bound.
#include "emlt/path/path.h"

namespace emlt::geometry_aware {

// The end margin, as a fraction of L.
inline constexpr double kConeEndMargin = 1e-3;

// The cheap bound's ends left to the exact walk, each as a fraction of L; the least step of
// its march as a fraction of the sample's clearance; its limits before the floor.
inline constexpr double kFieldEndFraction = 0.125;
inline constexpr double kFieldLeastStep = 0.25;
inline constexpr int kFieldMaxLowerings = 16;
inline constexpr int kFieldMaxSamples = 64;

enum class ConeMethod { Exact, Field, Cells };  // Cells: cone_cells.h

// The walk's own result for two surface (or camera) ends: t = tan α* where tan_min < t <
// tan_max, the exact cone, whatever the limits (the walk finds the same minimum from any
// starting cone); t ≤ tan_min where α* ≤ alpha_min, and t = tan_max where α* reaches alpha_max
// (tan_max is the tangent of alpha_max, or of just under π/2 for wider limits).
struct ConeTan {
  double t, tan_min, tan_max;
};
ConeTan estimate_cone_tan(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                          double alpha_min, double alpha_max);

// The exact estimate itself (no cache). An environment vertex at either end gives alpha_max.
double estimate_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                                double alpha_min, double alpha_max);

// The cheap conservative bound (no cache): at most estimate_cone_half_angle's value (up to
// its rounding), alpha_max for an environment vertex.
double field_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                             double alpha_min, double alpha_max);

// Any of them, through the per-thread cache of exact keys (cell_fraction: for Cells, f).
double cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                       double alpha_min, double alpha_max, ConeMethod method = ConeMethod::Exact,
                       double cell_fraction = 0.0);

}  // namespace emlt::geometry_aware
