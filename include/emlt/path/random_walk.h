#pragma once
// Subpath generation: the random walks BDPT runs and MLT's bidirectional mutation reruns
// to regenerate a deleted stretch of a path. A subpath is stored from its endpoint
// outwards: a light subpath is y0 (on an emitter) y1 ...; a camera subpath is z0 (on the
// lens) z1 .... Every new vertex gets its density from its predecessor in the walk's
// direction, and the predecessor's predecessor gets its density in the other direction
// (BsdfSample::pdf_reverse), both converted as vertex.h describes.
#include <algorithm>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/core/sample_source.h"
#include "emlt/path/vertex.h"
#include "emlt/scene/scene.h"

namespace emlt {

struct WalkLimits {
  int max_vertices = 2;  // the subpath's length cap, endpoint included
  int rr_depth = -1;     // Russian roulette once the subpath has this many segments; -1: never
};

// WalkLimits::rr_depth of a bidirectional estimator (bdpt, PSSMLT's bdpt tracer, the MLT
// bootstrap) for the scene's rrDepth: roulette may end a subpath from its rr_depth-th
// segment on, where Mitsuba's bidirectional integrators start it (they count a supernode
// ahead of each subpath's endpoint, `t >= rrDepth`). Starting one segment later made a
// bdpt sample trace a fifth more rays than Mitsuba's for the same rrDepth, for less than
// that in variance (docs/performance.md). The path tracer keeps "after rr_depth segments".
inline int subpath_rr_depth(int rr_depth) {
  return rr_depth < 0 ? -1 : std::max(rr_depth - 1, 0);
}

// Samples a light (by power), an emission ray and then walks in importance mode.
// Clears `subpath`; returns its vertex count (0 when no light emits).
int generate_light_subpath(const Scene& scene, Rng& rng, const WalkLimits& limits,
                           PathVertices& subpath, InvalidCounter* invalid = nullptr);
int generate_light_subpath(const Scene& scene, SampleSource& samples, const WalkLimits& limits,
                           PathVertices& subpath, InvalidCounter* invalid = nullptr);

// The camera ray through `raster` (lens sample u_lens), then a walk in radiance mode.
// An escaping ray adds an environment vertex when the scene has a sky.
int generate_camera_subpath(const Scene& scene, Rng& rng, const Vec2& raster, const Vec2& u_lens,
                            const WalkLimits& limits, PathVertices& subpath,
                            InvalidCounter* invalid = nullptr);
int generate_camera_subpath(const Scene& scene, SampleSource& samples, const Vec2& raster,
                            const Vec2& u_lens, const WalkLimits& limits,
                            PathVertices& subpath, InvalidCounter* invalid = nullptr);

// Extends `subpath` by at most `steps` vertices from its last vertex, which must have a
// predecessor in the vector (it supplies the incoming direction). Radiance mode walks
// towards the lights (camera subpaths), importance mode towards the camera. Stops early at
// an escape, an absorbed or invalid sample, or Russian roulette (rr_depth counts the
// subpath's segments; -1 disables it, as MLT mutations require). Returns vertices added.
int random_walk(const Scene& scene, Rng& rng, TransportMode mode, int steps, int rr_depth,
                PathVertices& subpath, InvalidCounter* invalid = nullptr);
int random_walk(const Scene& scene, SampleSource& samples, TransportMode mode, int steps,
                int rr_depth, PathVertices& subpath, InvalidCounter* invalid = nullptr);

}  // namespace emlt
