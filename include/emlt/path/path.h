#pragma once
// A whole path x0 (on an emitter or the sky) ... xk (on the lens), the unit MLT works on.
// Built by joining a light and a camera subpath (what a BDPT strategy samples); carries
// its densities in both directions for every vertex, its Heckbert type and its pixel.
#include <span>
#include <vector>

#include "emlt/path/path_density.h"
#include "emlt/path/path_type.h"
#include "emlt/path/vertex.h"
#include "emlt/scene/scene.h"

namespace emlt {

struct Path {
  PathVertices vertices;  // x0 ... xk
  PathType type;

  int edges() const { return int(vertices.size()) - 1; }
  const PathVertex& camera_vertex() const { return vertices.back(); }
  // Raster position of the camera vertex (where the path lands on the film).
  Vec2 raster() const { return vertices.back().raster; }
};

PathType compute_path_type(std::span<const PathVertex> vertices);

// Joins light[0..s) with camera[0..t) reversed into `out` and fills in the densities the
// join changes (path_density.h: connection_densities). For t = 1, `camera` holds the lens
// vertex sampled for the connection. Checks structure only, not visibility or throughput:
// false when s + t < 2, a span is too short, t = 0, the path would exceed kMaxPathVertices,
// or (s = 0) the last camera vertex is not on an emitter.
bool join_subpaths(const Scene& scene, std::span<const PathVertex> light, int s,
                   std::span<const PathVertex> camera, int t, Path& out);

// The stored densities, in path order.
std::vector<VertexDensity> path_densities(const Path& path);
// p_s of the path from its stored densities.
double path_density(const Path& path, int s);

// Recomputes every vertex's two densities from the geometry, the BSDFs, the lights and the
// camera alone (what a mutation does after changing vertices; also the check of the
// bookkeeping). Dirac vertices keep their stored lobe probability.
void recompute_densities(const Scene& scene, Path& path);
// The same after only vertices [first, last] changed (their records, not their number):
// a density depends on its vertex and the two before it (from the light) or after it (from
// the eye), so only pdf_from_light of [first, last + 2] and pdf_from_eye of [first - 2,
// last] are recomputed; the rest must already be what a full recomputation would give (true
// of every path the mutations and the bootstrap hand out). The values are bit-identical to
// a full recomputation, at a fraction of its cost for long paths and local moves.
void recompute_densities(const Scene& scene, Path& path, int first, int last);

// Dirac vertices contribute the value stored by the walk that crossed them, in the
// side-symmetric convention of vertex.h, so f is a function of the path alone and f / p_s
// is the BDPT estimate of split s for every s, refractions included.
//
// The measurement contribution f(x) in RGB: Le * prod(vertex factors) * prod(G) * W_e, with
// every edge assumed visible (paths come from walks and checked connections). In double:
// a product of many G = cos cos / d^2 underflows float in scenes modelled in millimetres
// (f of a 9-vertex Cornell-box path is about 1e-54). Non-finite results are dropped (zero)
// and counted.
DVec3 path_contribution(const Scene& scene, const Path& path, InvalidCounter* invalid = nullptr);
// f*, the scalar Metropolis target: the luminance of the whole RGB contribution.
double path_luminance(const Scene& scene, const Path& path);

}  // namespace emlt
