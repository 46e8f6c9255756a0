#pragma once
// The path samplers a primary-sample-space chain drives: f(u) for a vector u of unit-cube
// coordinates (primary_sample_vector.h), as the colour contributions the sample makes and
// where on the film they land.
//   - PathTracer: Kelemen's PSSMLT over the path tracer (next-event estimation, MIS); one
//     contribution at the sampled raster position.
//   - Bdpt: Kelemen's PSSMLT over BDPT, every strategy MIS-weighted; the t = 1 strategies
//     land wherever they hit the film.
//   - Multiplexed: Hachisuka et al.'s MMLT: paths of one length k only; the first connection
//     coordinate picks the strategy (s, t = k + 1 - s) among the k + 1 with t >= 1, and the
//     contribution is the MIS-weighted one divided by the selection probability 1 / (k + 1).
// Streams: 0 the raster, lens and camera subpath; 1 the light subpath; 2 the connections.
#include <vector>

#include "emlt/integrators/pss/primary_sample_vector.h"
#include "emlt/path/path_density.h"
#include "emlt/path/vertex.h"
#include "emlt/scene/scene.h"
#include "emlt/settings/settings.h"

namespace emlt {

enum class PssTracer { PathTracer, Bdpt, Multiplexed };

struct PssSplat {
  Vec2 raster;
  Rgb value;
};

// One evaluation: its splats and f* = the sum of their luminances; `length`, the segments
// of the longest path among its contributions (0: none), for the statistics.
struct PssSample {
  std::vector<PssSplat> splats;
  double target = 0.0;
  int length = 0;
  void clear() {
    splats.clear();
    target = 0.0;
    length = 0;
  }
};

class PrimarySampleTracer {
 public:
  // Paths of min_edges..max_edges segments count. `ignore_selection` (tests only): MMLT
  // without the division by the strategy's selection probability.
  PrimarySampleTracer(const Scene& scene, const RenderSettings& settings, PssTracer kind,
                      int min_edges, int max_edges, bool ignore_selection = false);

  // f(u) for the chain's vector (coordinates read through `rng` as the vector mutates
  // them); `length`: the path length of an MMLT chain (ignored otherwise).
  void evaluate(PrimarySampleVector& u, Rng& rng, int length, PssSample& out) const;

  PssTracer kind() const { return kind_; }

 private:
  struct Scratch {
    PathVertices light, camera;
    VertexDensity densities[kMaxPathVertices];
  };
  // Strategy (s, t) of the subpaths in scratch, MIS-weighted; adds its splat to `out`.
  void connect(int s, int t, Scratch& scratch, SampleSource& connection, double scale,
               PssSample& out) const;

  const Scene& scene_;
  const RenderSettings& settings_;
  RenderSettings path_tracer_settings_;  // settings_ with max_depth = max_edges
  PssTracer kind_;
  int min_edges_, max_edges_;
  bool ignore_selection_;
};

}  // namespace emlt
