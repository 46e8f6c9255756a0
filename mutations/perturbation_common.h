#pragma once
// Pieces shared by Veach's perturbations (lens, caustic, multi-chain; Veach 1997 §11.4.3):
// the 1/r image-plane offset, the 1/θ angular offset, walking
// through a specular chain with the same Dirac lobes, and the Jacobians that turn the
// perturbations' densities (image plane, solid angle) into the area-product measure the
// path layer's f and densities are written in.
//
// The measure. The path layer stores f and every sampling density in "area measure", with
// a Dirac vertex's lobe handled like a density (vertex.h). Call that reference measure ν:
// f is the target density w.r.t. ν, and a walk's density w.r.t. ν is the product of the
// stored vertex densities. A perturbation maps a low-dimensional variable (an image point,
// a direction) deterministically onto the moved vertices, so its proposal density w.r.t. ν
// is (density of the variable) x |d variable / d ν|, and that Jacobian is what a walk
// sampling the same variable uniformly would report as its density, divided by the lobe
// probabilities (the perturbation keeps each lobe instead of choosing it).
#include <functional>
#include <optional>

#include "emlt/mcmc/mutation.h"
#include "emlt/path/connection.h"

namespace emlt::perturbation {

// Veach's image-plane offset in pixels: radius R = r_max exp(-ln(r_max/r_min) u.x), angle
// 2π u.y. Its density over the plane, 1 / (2π |Δ|² ln(r_max/r_min)) on r_min ≤ |Δ| ≤ r_max,
// depends on |Δ| only, so the move and its reverse have the same density.
Vec2 sample_image_offset(float r_min, float r_max, const Vec2& u);

// A direction at angle θ = θ_max exp(-ln(θ_max/θ_min) u.x) from w, azimuth 2π u.y. Its
// solid-angle density 1 / (2π ln(θ_max/θ_min) θ sin θ) depends on θ only (symmetric in the
// two directions) as long as both moves use the same range.
Vec3 perturb_direction(const Vec3& w, double theta_min, double theta_max, const Vec2& u);

// Angle between two directions, accurate for tiny angles (atan2 of |a×b| and a·b in double).
double angle_between(const DVec3& a, const DVec3& b);
// Unit direction between two vertices in double (small perturbation angles need it).
DVec3 precise_direction(const PathVertex& from, const PathVertex& to);

// Whether the Dirac interaction at v (between neighbours a and b) crossed the surface, so
// a perturbation keeps refraction as refraction and reflection as reflection.
bool crosses_surface(const PathVertex& v, const PathVertex& a, const PathVertex& b);

// The surface vertex a ray reaches, or nothing (an escape, or a hit without a BSDF).
std::optional<PathVertex> trace_surface(const Scene& scene, const Ray& ray);

// The direction leaving Dirac vertex v when the walk arrives from `w_back` (world, unit,
// towards the walk's previous vertex) and keeps a delta lobe of the same kind (reflection
// or transmission). The lobe is found by probing Bsdf::sample with a few lobe numbers: every
// BSDF of the project picks its lobes by thresholds of u_lobe and returns a delta lobe's
// direction independently of u (documented assumption; no BSDF interface change needed).
// Empty when no such lobe exists there (the path type would change) or the direction is on
// inconsistent sides of the shading and geometric normals.
// `eta`, when given, receives the lobe's relative IOR crossed (n on the side left towards
// over n on the side arrived from; 1 for a reflection).
std::optional<Vec3> continue_through_delta(const PathVertex& v, const Vec3& w_back,
                                           TransportMode mode, bool transmission,
                                           float* eta = nullptr);

// Fills v's Dirac record (probability, value, IOR ratio) for the path through it between
// eye-side neighbour `eye` and light-side neighbour `light`, exactly as random_walk would
// when walking in `mode` (radiance: from the eye; importance: from the light). False when
// the lobe no longer exists.
bool fill_delta_record(PathVertex& v, const PathVertex& eye, const PathVertex& light,
                       TransportMode mode, bool transmission);

// The path layer stores Dirac values in one side-symmetric convention (vertex.h), so a
// value recomputed in either transport mode matches the stored one for flat geometry; with
// interpolated shading normals the two modes' shading corrections can still differ. A
// perturbation recomputes the values it moves in one mode; this returns
// log(f recomputed in that mode / f as stored) over x's Dirac vertices in [first, last],
// which the acceptance ratio adds so that f(x) and f(y) are compared consistently.
double log_convention_correction(const Path& x, int first, int last, TransportMode mode);

// log T(y->x)/T(x->y) of a move that rebuilt the eye side of x beyond the fixed vertex l
// from a symmetric image-plane (and angular) step: the eye-side Jacobians of both paths
// (dropped when `include_jacobian` is false, a test-only bug) and x's convention correction.
double eye_side_log_ratio(const Path& x, const Path& y, int l, bool include_jacobian);

// log of the Jacobian |d(image point, directions at interior non-specular vertices) / dν|
// of vertices [first, k-1] of a path walked from the eye (the lens point and everything
// light-side of `first` fixed): the product over those vertices of their density from the
// eye-side neighbour divided by that neighbour's directional density (1 for the camera,
// whose raster-to-direction density is part of the Jacobian; the lobe probability for a
// Dirac vertex; the solid-angle density itself for a non-specular vertex whose outgoing
// direction is the perturbed variable). Needs recompute_densities to have run.
double log_eye_jacobian(const Path& path, int first);

// The same for vertices [first, last] walked from the light from a fixed vertex first - 1
// whose outgoing direction is the perturbed variable (the caustic perturbation).
double log_light_jacobian(const Path& path, int first, int last);

// Angular size of one pixel at the image centre (radians), for Veach's caustic heuristic;
// the camera computes it once (Camera::radians_per_pixel).
double radians_per_pixel(const Camera& camera);

bool on_film(const Camera& camera, const Vec2& raster);

// Re-aims the path's lens vertex at `seen`, the moved vertex next to it: a kept lens point's
// raster becomes where it sees `seen`; an orthographic camera's film point moves to seen's
// projection, with its raster (camera.h: a function of `seen`, no density of its own).
// False when `seen` lands outside the film.
bool aim_lens_at(const Scene& scene, PathVertex& lens, const PathVertex& seen);

// The image-plane move shared by the lens and multi-chain perturbations: rebuilds y's
// vertices [l+1, k-1] by tracing from x's lens point through `raster` towards the light.
// Each vertex that was Dirac in x must again take a delta lobe of the same kind; at an
// interior non-specular vertex i (l+1 < i < k) the outgoing direction is
// interior_direction(i, x's direction from x_i towards x_{i-1}) (the multi-chain angular
// step; the lens perturbation has none). Dirac records are filled in the radiance
// convention, then y_{l+1} is connected to the fixed x_l (l = -1: the walk itself must end on
// an emitting surface, y_0, and there is no connection), y's type checked and the densities
// that depend on the moved vertices recomputed (the rest are x's, which must be current, as
// on every chain path: the bootstrap's seeds and all proposals). False on any failure
// (escape, lobe lost, occlusion, zero contribution).
using InteriorDirection = std::function<std::optional<Vec3>(int index, const Vec3& old_direction)>;
bool rebuild_eye_side(const Scene& scene, const Path& x, int l, const Vec2& raster,
                      const InteriorDirection& interior_direction, Path& y);

// Whether y, a copy of x with some vertices replaced, has x's path type and the structure
// MLT needs (emitter first, lens last, surfaces between); if so, recomputes y's densities.
bool finish_proposal(const Scene& scene, const Path& x, Path& y);
// The same when only y's vertices [first, last] differ from x's (x's densities being
// current): only the densities that depend on them are recomputed (path.h).
bool finish_proposal(const Scene& scene, const Path& x, Path& y, int first, int last);

}  // namespace emlt::perturbation
