#pragma once
// Evaluating path vertices and joining two of them: the pieces of f(x) and p(x) that BDPT's
// connections, its MIS weights and MLT's bidirectional mutation all need. Conventions are
// those of vertex.h.
#include <optional>

#include "emlt/path/vertex.h"
#include "emlt/scene/scene.h"

namespace emlt {

// The vertex's factor of the measurement contribution f, for light arriving from
// `light_side` and leaving towards `eye_side`, in the radiance convention:
//   light_side == nullptr (x0):  emitted radiance towards eye_side,
//   eye_side == nullptr (xk):    camera importance W_e towards light_side,
//   otherwise:                   f_s(eye dir, light dir) * |w_light.ns| / |w_light.ng|,
// where the last factor moves the shading cosine into the BSDF so that G can use geometric
// normals (Veach 1997 §5.3; for light subpaths it is the adjoint correction). Directions on
// inconsistent sides of the geometric and shading normals give zero (no light leaks).
// A Dirac vertex returns the value stored when it was sampled.
Rgb vertex_factor(const Scene& scene, const PathVertex& v, const PathVertex* light_side,
                  const PathVertex* eye_side);

// The straight segment from one vertex to the next, computed once: unit direction as
// direction_between(from, to) gives it, and the squared distance (meaningless when either
// end is the sky). The reverse segment's direction is exactly -w, so a loop along a path
// can share one Segment between the two vertices of an edge without changing a bit.
// Trivial (no member initialisers), so a loop's local array of them costs nothing to declare.
struct Segment {
  Vec3 w;
  float distance_squared;
};
inline Segment segment_between(const PathVertex& from, const PathVertex& to) {
  if (to.is_environment() || from.is_environment()) return {direction_between(from, to), 0.0f};
  const Vec3 d = to.position - from.position;
  const float distance_squared = glm::dot(d, d);
  const float length = std::sqrt(distance_squared);  // glm::length's arithmetic
  return {length > 0.0f ? d / length : Vec3(0.0f), distance_squared};
}

// geometry_term(a, b) and solid_angle_to_vertex_measure(pdf, from, to) from the segment
// a -> b (from -> to): the same values, without recomputing the direction.
inline float geometry_term_along(const PathVertex& a, const PathVertex& b, const Segment& ab) {
  if (a.kind == VertexKind::OrthographicCamera) return orthographic_geometry_term(a, b);
  if (b.kind == VertexKind::OrthographicCamera) return orthographic_geometry_term(b, a);
  if (a.is_environment() && b.is_environment()) return 0.0f;
  if (a.is_environment() || b.is_environment()) return abs_cos_at(a, ab.w) * abs_cos_at(b, ab.w);
  if (!(ab.distance_squared > 0.0f)) return 0.0f;
  const float g = abs_cos_at(a, ab.w) * abs_cos_at(b, ab.w) / ab.distance_squared;
  return std::isfinite(g) ? g : 0.0f;
}
inline float solid_angle_along(float pdf_solid_angle, const PathVertex& to, const Segment& out) {
  if (to.is_environment()) return pdf_solid_angle;  // the sky's measure is solid angle
  if (!(out.distance_squared > 0.0f)) return 0.0f;
  const float pdf = pdf_solid_angle * abs_cos_at(to, out.w) / out.distance_squared;
  return std::isfinite(pdf) ? pdf : 0.0f;
}

// vertex_factor and pdf_towards with the segments to the neighbours already known
// (w_light / w_eye: unit directions from v towards its light- / eye-side neighbour, null
// where vertex_factor's neighbour is null; `out` from `from` to `to`, `back` from `from` to
// `before`). The same arithmetic as the plain versions, for loops that meet every edge twice.
Rgb vertex_factor_along(const Scene& scene, const PathVertex& v, const Vec3* w_light,
                        const Vec3* w_eye);
float pdf_towards_along(const Scene& scene, const PathVertex* before, const PathVertex& from,
                        const PathVertex& to, const Segment& out, const Vec3* back);
// pdf_towards_along with `from` evaluated by its smooth lobes, as if its `delta` were false:
// the density a connection end has inside the connected path (path_density.h).
float smooth_pdf_towards_along(const Scene& scene, const PathVertex* before, const PathVertex& from,
                               const PathVertex& to, const Segment& out, const Vec3* back);

// Unoccluded straight segment between two vertices (one may be the sky).
bool mutually_visible(const Scene& scene, const PathVertex& a, const PathVertex& b);

// Deterministic connection of light-subpath end y (light-side neighbour y_prev, null when
// y is x0) to eye-subpath end z (eye-side neighbour z_prev, null when z is the camera):
// vertex_factor(y) * G(y, z) * vertex_factor(z) with visibility, or zero when either end
// is purely specular, faces away, or the segment is blocked. Throughputs not included.
// The ends are evaluated by their smooth lobes whatever lobe a walk sampled there to go on:
// a path that ends at a vertex does not contain that continuation.
Rgb connect_vertices(const Scene& scene, const PathVertex* y_prev, const PathVertex& y,
                     const PathVertex& z, const PathVertex* z_prev);

// Density, in `to`'s measure, with which a walk standing at `from` and having arrived from
// `before` samples `to` next. `before == nullptr` means `from` is an endpoint: a camera
// vertex samples by its ray distribution, an emitter vertex by its emission distribution.
// A Dirac vertex uses its stored lobe probability.
float pdf_towards(const Scene& scene, const PathVertex* before, const PathVertex& from,
                  const PathVertex& to);

// Density with which light sampling picks emitter vertex v as x0: selection probability
// times the area density of the point (area lights) or the direction's density (sky).
float pdf_light_origin(const Scene& scene, const PathVertex& v);

// The camera vertex for a t = 1 connection to light-subpath end y: a lens point (u_lens)
// seeing y, with its raster position, throughput 1 / (lens area density) and densities set.
// Empty when y projects outside the film or is behind the camera.
std::optional<PathVertex> sample_camera_vertex(const Scene& scene, const PathVertex& y,
                                               const Vec2& u_lens);

}  // namespace emlt
