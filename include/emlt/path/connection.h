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
