#pragma once
// Memoised cones of quantised segments (`--gamlt-cone cells`, the default): the occluder-free
// cone of cone.h made a function of a coarse key, so that the perturbations' nearby states
// share it.
//
// Why. The exact walk costs more than a whole MLT mutation (docs/performance.md), and each
// proposal needs its own cone, since its endpoints are new floats. But the perturbations move
// vertices a little: a lens move keeps x_l and moves x_{l+1} by a few pixels' footprint, so
// most proposals' segments run between the same two small regions as some recent state's.
//
// The key. The segment's length L picks a level of a world grid aligned with the scene's
// box: cells of side h = E 2^-k (E the box's longest side), the coarsest with h ≤ f L (f the
// cell fraction, `--gamlt-cone-cell`). Each endpoint gives its cell at that level and its
// surface: for a point on a triangle, the plane (the geometric normal rounded to 2^-16 and
// the plane's offset rounded to E 2^-20); on an analytic sphere, the sphere; a camera vertex
// its exact position (a pinhole is one point; nothing to quantise).
//
// The value is a function of the key and the caller's limits only: clamp(α*, alpha_min,
// alpha_max), α* the exact cone of the key's canonical segment, between the cell centres
// projected onto the endpoints' surfaces (so that the own-surface rule of cone.h still leaves
// each end's wall or sphere out). The walk (estimate_cone_tan) runs over the limits rounded
// outwards to powers of 2^(1/4); where its result lies strictly between its bounds it is
// tan α* itself, whatever the limits, so the entry then serves any limits; at a bound it
// serves only the same rounded limits (the same walk) or, at its ceiling, any lower ceiling
// and, at its floor, any higher floor. A per-thread four-way table (the whole key stored and
// compared, recomputed on a mismatch or limits it does not serve) thus returns the same bits
// as a recomputation: the cone is a
// deterministic function of the state, independent of the table's history, the thread and
// the order of the chains, which is all the perturbations' acceptance needs (the reverse
// density already uses y's own cone). Like the exact cones' cache, the table knows a scene by
// its address (one scene at a time per process).
//
// What it gives up. The cone is that of a segment up to about √3 h from the real one at each
// end, so it may be wider or narrower than the real segment's by about the cells' angular
// size seen from the other end, about √3 f rad: not conservative. That only changes which step
// ranges the moves use (their efficiency), not the target, and is measured in
// docs/performance.md ("Memoised cones of quantised segments").
#include <cstdint>

#include "emlt/path/path.h"

namespace emlt::geometry_aware {

// What a cell cone depends on (besides the scene).
struct CellKey {
  int32_t level = 0;
  struct End {
    int32_t kind = 0;         // EndKind
    int32_t surface[3] = {};  // plane: the rounded normal; sphere: its index; camera: position bits
    int64_t offset = 0;       // plane: the rounded offset
    int64_t cell[3] = {};     // plane and sphere
    bool operator==(const End&) const = default;
  } ends[2];  // apex, other
  bool operator==(const CellKey&) const = default;
};

// Injected bugs, tests only.
struct CellConeBugs {
  bool key_without_other_cell = false;  // the key leaves out the far endpoint's cell
};

// The key of the segment apex -> other, or false where the segment is not quantised (an
// environment vertex, a zero length, a scene without triangles): the caller then uses the
// exact cone.
bool cell_key(const Scene& scene, const PathVertex& apex, const PathVertex& other, double fraction,
              CellKey* key);

// The key's cone under the limits, without the table: clamp(α*, alpha_min, alpha_max), α* the
// exact cone of the key's canonical segment.
double cell_key_cone(const Scene& scene, const CellKey& key, double alpha_min, double alpha_max);

// This thread's table lookups and how many of them computed the cone (tests, measurements).
struct CellConeCounts {
  uint64_t lookups = 0, computed = 0;
};
CellConeCounts cell_cone_counts();

// The cone through this thread's table, clamped to [alpha_min, alpha_max]; the exact cone
// (cone_half_angle) where the segment has no key.
double cell_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                            double alpha_min, double alpha_max, double fraction,
                            CellConeBugs bugs = {});

}  // namespace emlt::geometry_aware
