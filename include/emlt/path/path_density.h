#pragma once
// The density p_s(x) of generating a path x0 ... x_{n-1} with s light-side and t = n - s
// eye-side vertices (Veach 1997 §10.2):
//     p_s = prod_{i<s} pdf_from_light(x_i) * prod_{i>=s} pdf_from_eye(x_i),
// zero when the split would connect at a Dirac vertex or needs the lens to be hit (t = 0).
// BDPT's MIS weights and MLT's bidirectional-mutation densities both come from here, from
// the densities stored in the vertices: nothing is recomputed per strategy.
#include <span>

#include "emlt/path/vertex.h"
#include "emlt/settings/settings.h"

namespace emlt {

// What a split needs to know about one vertex of the path, in path order.
struct VertexDensity {
  float from_light = 0.0f;
  float from_eye = 0.0f;
  bool delta = false;        // a Dirac interaction inside the path: no split may end here
  bool environment = false;  // x0 is the sky
  bool camera = false;
  bool delta_emitter = false;  // x0 is on a point or directional light
};

inline VertexDensity density_of(const PathVertex& v) {
  return {v.pdf_from_light, v.pdf_from_eye, v.delta, v.is_environment(), v.is_camera(),
          v.is_delta_emitter()};
}

// Whether the split (s light-side vertices) is a strategy BDPT can sample this path with.
bool split_is_possible(std::span<const VertexDensity> path, int s);

// p_s; zero for impossible splits.
double split_density(std::span<const VertexDensity> path, int s);

// MIS weight of split s among every possible split of the same path, by the balance,
// power or maximum heuristic (second-order: balance), from the ratios p_{s'}/p_s accumulated vertex by vertex (Veach's
// eq. 10.9): numerically safe even when the densities themselves over- or underflow.
double mis_weight(std::span<const VertexDensity> path, int s, MisHeuristic heuristic);

// The densities of the path that joining light[0..s) with camera[0..t) (reversed) forms,
// with the four values the connection changes recomputed: the two connection ends seen
// from the other side, and their neighbours seen through them. `camera` for t = 1 is the
// sampled lens vertex alone; for s = 0, camera[t-1] must lie on an emitter.
// `out` must hold s + t entries (at most kMaxPathVertices).
void connection_densities(const Scene& scene, std::span<const PathVertex> light, int s,
                          std::span<const PathVertex> camera, int t, std::span<VertexDensity> out);

inline constexpr int kMaxPathVertices = 64;

}  // namespace emlt
