#pragma once
// A path written to and read back from a checkpoint bit for bit. Vertices refer to the
// scene's BSDFs and lights by pointer; in the checkpoint those become indices (of the
// scene's materials and of its light set), which a scene built from the same files maps
// back to the same objects.
#include <unordered_map>

#include "emlt/core/state_io.h"
#include "emlt/path/path.h"

namespace emlt {

class PathCodec {
 public:
  explicit PathCodec(const Scene& scene);

  void save(const Path& path, StateWriter& out) const;
  // Throws StateError for a path this scene cannot hold (an index out of range, too many
  // vertices).
  Path load(StateReader& in) const;

  // The fast form for paths passed between the ranks of one run (EMLT's swaps, cluster.h):
  // each vertex record copied whole, its BSDF and light as indices, no checks (the data
  // never left the run). `unpack` reuses the path's storage.
  void pack(const Path& path, StateWriter& out) const;
  void unpack(StateReader& in, Path& path) const;

  // The guide form: what EMLT reads of a path of the frozen ensemble Y (EnsembleGuides and,
  // through GuideView, the guided strategies): its type and every vertex's kind, position
  // and sky direction, and the camera vertex's raster position; about a fifth of the whole
  // path. MPI ranks send the paths they moved in this form, since the other ranks only ever
  // read them as guides. `unpack_guide` leaves every other field of the vertices at its
  // default (a guide copy is never moved, splatted or saved as a chain).
  static void pack_guide(const Path& path, StateWriter& out);
  static void unpack_guide(StateReader& in, Path& path);

 private:
  const Scene& scene_;
  std::vector<const Bsdf*> bsdfs_;
  std::unordered_map<const Bsdf*, int32_t> bsdf_index_;
  std::unordered_map<const Light*, int32_t> light_index_;
};

}  // namespace emlt
