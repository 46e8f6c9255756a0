#include "emlt/path/path_density.h"

#include "emlt/path/connection.h"

namespace emlt {

bool split_is_possible(std::span<const VertexDensity> path, int s) {
  const int n = int(path.size());
  if (s < 0 || s >= n) return false;  // t = 0 would need a walk to hit the lens
  // No camera walk hits a delta light, and none is seen from the lens (connection.h).
  if (path[0].delta_emitter && (s == 0 || (s == 1 && n == 2))) return false;
  if (s == 0) return true;            // the camera walk hits x0; its density decides
  if (path[size_t(s - 1)].delta || path[size_t(s)].delta) return false;
  // Light tracing from a sky direction straight into the lens is not a sampled strategy
  // (connection.h: sample_camera_vertex).
  if (s == 1 && path[0].environment && path[1].camera) return false;
  return true;
}

double split_density(std::span<const VertexDensity> path, int s) {
  if (!split_is_possible(path, s)) return 0.0;
  double density = 1.0;
  for (int i = 0; i < int(path.size()); ++i)
    density *= i < s ? double(path[size_t(i)].from_light) : double(path[size_t(i)].from_eye);
  return density;
}

double mis_weight(std::span<const VertexDensity> path, int s, MisHeuristic heuristic) {
  const int n = int(path.size());
  // The maximum heuristic: 1 where no other split has a larger density, shared evenly
  // with the splits that tie (so that the weights of a path still sum to one).
  if (heuristic == MisHeuristic::Max) {
    int ties = 0;
    bool beaten = false;
    const auto visit = [&](double ratio) {
      if (ratio > 1.0) beaten = true;
      else if (ratio == 1.0) ++ties;
    };
    double ratio = 1.0;
    for (int i = s; i < n - 1; ++i) {
      const VertexDensity& x = path[size_t(i)];
      ratio = x.from_eye > 0.0f ? ratio * double(x.from_light) / double(x.from_eye) : 0.0;
      if (split_is_possible(path, i + 1)) visit(ratio);
    }
    ratio = 1.0;
    for (int i = s - 1; i >= 0; --i) {
      const VertexDensity& x = path[size_t(i)];
      ratio = x.from_light > 0.0f ? ratio * double(x.from_eye) / double(x.from_light) : 0.0;
      if (split_is_possible(path, i)) visit(ratio);
    }
    return beaten ? 0.0 : 1.0 / double(1 + ties);
  }
  // SecondOrder has no split between many strategies: its paths weigh as Balance's.
  const auto term = [heuristic](double ratio) {
    return heuristic == MisHeuristic::Power ? ratio * ratio : ratio;
  };
  double sum = 1.0;  // the split itself: p_s / p_s
  // Towards the eye: p_{i+1} / p_i = from_light(x_i) / from_eye(x_i).
  double ratio = 1.0;
  for (int i = s; i < n - 1; ++i) {
    const VertexDensity& x = path[size_t(i)];
    ratio = x.from_eye > 0.0f ? ratio * double(x.from_light) / double(x.from_eye) : 0.0;
    if (split_is_possible(path, i + 1)) sum += term(ratio);
  }
  // Towards the light: p_{i} / p_{i+1} = from_eye(x_i) / from_light(x_i).
  ratio = 1.0;
  for (int i = s - 1; i >= 0; --i) {
    const VertexDensity& x = path[size_t(i)];
    ratio = x.from_light > 0.0f ? ratio * double(x.from_eye) / double(x.from_light) : 0.0;
    if (split_is_possible(path, i)) sum += term(ratio);
  }
  const double weight = 1.0 / sum;
  return std::isfinite(weight) ? weight : 0.0;
}

void connection_densities(const Scene& scene, std::span<const PathVertex> light, int s,
                          std::span<const PathVertex> camera, int t, std::span<VertexDensity> out) {
  const int n = s + t;
  for (int i = 0; i < s; ++i) out[size_t(i)] = density_of(light[size_t(i)]);
  for (int i = s; i < n; ++i) out[size_t(i)] = density_of(camera[size_t(n - 1 - i)]);
  // The connection ends are evaluated by their smooth lobes (connection.h), so inside this
  // path they are not Dirac vertices whatever lobe a walk went on with.
  if (s >= 1) out[size_t(s - 1)].delta = false;
  if (t >= 1) out[size_t(s)].delta = false;

  if (s == 0) {
    // (Neither density of an emitter end reads its `delta`.)
    const PathVertex& emitter = camera[size_t(t - 1)];
    out[0].from_light = pdf_light_origin(scene, emitter);
    if (t >= 2) out[1].from_light = pdf_towards(scene, nullptr, emitter, camera[size_t(t - 2)]);
    return;
  }
  const PathVertex &y = light[size_t(s - 1)], &z = camera[size_t(t - 1)];
  const PathVertex* y_previous = s >= 2 ? &light[size_t(s - 2)] : nullptr;
  const PathVertex* z_previous = t >= 2 ? &camera[size_t(t - 2)] : nullptr;
  if (y.is_environment() && z.is_environment()) {
    // No segment joins two sky directions (and the shared segments below would not be
    // each other's reverse): the plain evaluation, ends made smooth by copies.
    PathVertex y_smooth = y, z_smooth = z;
    y_smooth.delta = z_smooth.delta = false;
    out[size_t(s)].from_light = pdf_towards(scene, y_previous, y_smooth, z_smooth);
    if (z_previous)
      out[size_t(s + 1)].from_light = pdf_towards(scene, &y_smooth, z_smooth, *z_previous);
    out[size_t(s - 1)].from_eye = pdf_towards(scene, z_previous, z_smooth, y_smooth);
    if (y_previous)
      out[size_t(s - 2)].from_eye = pdf_towards(scene, &z_smooth, y_smooth, *y_previous);
    return;
  }
  // The three segments the four densities use, each computed once: pdf_towards would
  // compute each of them two or three times, with the same arithmetic (connection.h:
  // the reverse of a segment is exactly -w; a zero-length one keeps the zero vector).
  const Segment yz = segment_between(y, z);
  const Segment zy{yz.distance_squared > 0.0f || y.is_environment() || z.is_environment()
                       ? -yz.w
                       : direction_between(z, y),
                   yz.distance_squared};
  Segment y_back{}, z_back{};
  if (y_previous) y_back = segment_between(y, *y_previous);
  if (z_previous) z_back = segment_between(z, *z_previous);
  out[size_t(s)].from_light =
      smooth_pdf_towards_along(scene, y_previous, y, z, yz, y_previous ? &y_back.w : nullptr);
  if (z_previous)
    out[size_t(s + 1)].from_light =
        smooth_pdf_towards_along(scene, &y, z, *z_previous, z_back, &zy.w);
  out[size_t(s - 1)].from_eye =
      smooth_pdf_towards_along(scene, z_previous, z, y, zy, z_previous ? &z_back.w : nullptr);
  if (y_previous)
    out[size_t(s - 2)].from_eye =
        smooth_pdf_towards_along(scene, &z, y, *y_previous, y_back, &yz.w);
}

}  // namespace emlt
