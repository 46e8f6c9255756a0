#include "emlt/integrators/pss/primary_sample_tracer.h"

#include <algorithm>

#include "emlt/integrators/path_tracer_estimate.h"
#include "emlt/path/connection.h"
#include "emlt/path/random_walk.h"

namespace emlt {

namespace {

constexpr int kCameraStream = 0, kLightStream = 1, kConnectionStream = 2;

// Scratch per thread: evaluations run in parallel on the chains' threads.
thread_local PathVertices t_light, t_camera;

}  // namespace

PrimarySampleTracer::PrimarySampleTracer(const Scene& scene, const RenderSettings& settings,
                                         PssTracer kind, int min_edges, int max_edges,
                                         bool ignore_selection)
    : scene_(scene),
      settings_(settings),
      path_tracer_settings_(settings),
      kind_(kind),
      min_edges_(min_edges),
      max_edges_(max_edges),
      ignore_selection_(ignore_selection) {
  path_tracer_settings_.max_depth = max_edges;
}

void PrimarySampleTracer::connect(int s, int t, Scratch& scratch, SampleSource& connection,
                                  double scale, PssSample& out) const {
  const auto& camera = scratch.camera;
  const auto& light = scratch.light;
  Rgb contribution(0.0f);
  PathVertex lens;
  std::span<const PathVertex> camera_side;
  if (t >= 2) camera_side = std::span<const PathVertex>(camera.data(), size_t(t));
  if (s == 0) {
    const PathVertex& z = camera[size_t(t - 1)];
    if (t < 2 || !z.is_emitter()) return;
    contribution = z.throughput * vertex_factor(scene_, z, nullptr, &camera[size_t(t - 2)]);
  } else {
    const PathVertex& y = light[size_t(s - 1)];
    const PathVertex* y_previous = s >= 2 ? &light[size_t(s - 2)] : nullptr;
    if (t == 1) {
      const auto sampled = sample_camera_vertex(scene_, y, connection.uniform2());
      if (!sampled) return;
      lens = *sampled;
      camera_side = std::span<const PathVertex>(&lens, 1);
      contribution =
          y.throughput * connect_vertices(scene_, y_previous, y, lens, nullptr) * lens.throughput;
    } else {
      const PathVertex& z = camera[size_t(t - 1)];
      contribution = y.throughput *
                     connect_vertices(scene_, y_previous, y, z, &camera[size_t(t - 2)]) *
                     z.throughput;
    }
  }
  if (is_black(contribution) || !is_finite(contribution)) return;
  const std::span<VertexDensity> densities(scratch.densities, size_t(s + t));
  connection_densities(scene_, std::span<const PathVertex>(light.data(), size_t(s)), s, camera_side,
                       t, densities);
  const Rgb value = contribution * float(mis_weight(densities, s, settings_.mis) * scale);
  if (is_black(value) || !is_finite(value)) return;
  out.splats.push_back({camera_side[0].raster, value});
  out.target += double(luminance(value));
  out.length = std::max(out.length, s + t - 1);
}

void PrimarySampleTracer::evaluate(PrimarySampleVector& u, Rng& rng, int length,
                                   PssSample& out) const {
  out.clear();
  PrimaryStream camera_stream(u, rng, kCameraStream), light_stream(u, rng, kLightStream),
      connection_stream(u, rng, kConnectionStream);
  const Camera& camera = scene_.camera();
  Scratch scratch{std::move(t_light), std::move(t_camera), {}};
  const auto give_back = [&] {
    t_light = std::move(scratch.light);
    t_camera = std::move(scratch.camera);
  };
  if (kind_ == PssTracer::Multiplexed) {
    // The strategy first, so that changing it moves no other coordinate.
    const int strategies = length + 1;  // s = 0 .. k, t = k + 1 - s >= 1
    const int s = std::min(int(connection_stream.uniform() * float(strategies)), strategies - 1);
    const int t = length + 1 - s;
    const Vec2 raster(camera_stream.uniform() * float(camera.width()),
                      camera_stream.uniform() * float(camera.height()));
    const Vec2 u_lens = camera_stream.uniform2();
    if (t >= 2 && generate_camera_subpath(scene_, camera_stream, raster, u_lens, {t, -1},
                                          scratch.camera) < t) {
      give_back();
      return;
    }
    if (s >= 1 && generate_light_subpath(scene_, light_stream, {s, -1}, scratch.light) < s) {
      give_back();
      return;
    }
    connect(s, t, scratch, connection_stream, ignore_selection_ ? 1.0 : double(strategies), out);
    give_back();
    return;
  }

  const Vec2 raster(camera_stream.uniform() * float(camera.width()),
                    camera_stream.uniform() * float(camera.height()));
  const Vec2 u_lens = camera_stream.uniform2();
  if (kind_ == PssTracer::PathTracer) {
    const Rgb value =
        path_tracer_estimate(scene_, path_tracer_settings_, camera.generate_ray(raster, u_lens),
                             camera_stream, min_edges_, &out.length);
    if (!is_black(value) && is_finite(value)) {
      out.splats.push_back({raster, value});
      out.target = double(luminance(value));
    } else {
      out.length = 0;
    }
    give_back();
    return;
  }
  // BDPT: every strategy of the two subpaths, as the bdpt integrator forms them.
  generate_camera_subpath(scene_, camera_stream, raster, u_lens,
                          {max_edges_ + 1, subpath_rr_depth(settings_.rr_depth)}, scratch.camera);
  generate_light_subpath(scene_, light_stream, {max_edges_, subpath_rr_depth(settings_.rr_depth)},
                         scratch.light);
  for (int t = 1; t <= int(scratch.camera.size()); ++t)
    for (int s = 0; s <= int(scratch.light.size()); ++s) {
      const int segments = s + t - 1;
      if (segments > max_edges_) break;
      if (segments < min_edges_) continue;
      connect(s, t, scratch, connection_stream, 1.0, out);
    }
  give_back();
}

}  // namespace emlt
