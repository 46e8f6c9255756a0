// `ptracer`: Mitsuba 0.6's particle tracer (adjoint particle tracing, or light tracing).
// Each path starts on a light, chosen by power, and walks in importance mode; every vertex,
// the light's own point included, is connected to the camera through a sampled lens point
// and splatted on the film where it lands. This is BDPT's t = 1 strategy alone and
// unweighted, on the same path layer (random_walk.h, connection.h), but for a non-box
// filter's pixels at the image's edge, which Mitsuba's ptracer does not renormalise (see
// sample()), and for the environment seen directly, which BDPT leaves to its camera paths
// and Mitsuba's ptracer draws: a light path leaving the sky connects its sky direction to
// the lens (sky_camera_vertex). It renders what a connection to the camera can see, so
// light reaching the camera only through a specular bounce (a light seen in a mirror or
// through glass) stays black, as in Mitsuba.
//
// Mitsuba's parameters: maxDepth is --max-depth (segments: 1 shows the lights only), rrDepth
// the scene's rr_depth (roulette from that many light-subpath segments, as BDPT's light
// side); granularity, the light paths of one work unit, only schedules work, which the pass
// runner's tiles do here. Mitsuba's ptracer reads no hideEmitters (it draws the lights seen
// directly), and bruteForce is reported as unsupported (both in the loader). The budget is
// --spp light paths per pixel, Mitsuba's sampleCount of paths per pixel: light path k of
// pixel i draws from the stream (seed, i, k), a key that gives the pass runner its order
// (the same bits at any thread or rank count, and resumed) and says nothing about where the
// path lands.
#include <optional>

#include "emlt/core/warp.h"
#include "emlt/path/connection.h"
#include "emlt/path/path_density.h"
#include "emlt/path/random_walk.h"
#include "emlt/run/integrator.h"
#include "emlt/run/pass_runner.h"

namespace emlt {

namespace {

// The lens vertex that sees sky vertex `sky` (a light path's origin on the environment):
// a lens point, and the film point of the sky's direction from it. Mitsuba's ptracer draws
// the environment seen directly (its particles leave a sphere round the scene and camera
// towards the lens); here the sky direction, drawn by the light's emission sampling, is
// itself the light vertex, in solid angle, so the lens point needs no distance term:
// throughput 1 / (lens area density), as for a point in the scene. An orthographic camera
// sees the sky in its one direction only, which no sampled direction is: none there.
std::optional<PathVertex> sky_camera_vertex(const Scene& scene, const PathVertex& sky,
                                            const Vec2& u_lens) {
  const Camera& camera = scene.camera();
  Vec3 lens_point = camera.position();
  if (!camera.is_pinhole()) {  // uniform on the aperture, in any basis of the lens plane
    const Vec2 disk = square_to_uniform_disk_concentric(u_lens) * camera.aperture_radius();
    lens_point += disk.x * camera.forward_frame().s + disk.y * camera.forward_frame().t;
  }
  const auto raster = camera.raster_position(lens_point, sky.sky_direction);
  if (!raster) return std::nullopt;
  PathVertex c = make_camera_vertex(scene, lens_point, *raster);
  float pdf_position = 0.0f, pdf_direction = 0.0f;
  camera.pdf_emission(sky.sky_direction, &pdf_position, &pdf_direction);
  if (!(pdf_position > 0.0f)) return std::nullopt;
  c.pdf_from_eye = pdf_position;
  c.throughput = Rgb(1.0f / pdf_position);
  return c;
}

class ParticleTracerStep final : public PixelSampleStep {
 public:
  ParticleTracerStep(const Scene& scene, const RenderSettings& settings)
      : scene_(scene), settings_(settings) {
    // A path of s light vertices and the lens has s segments; unbounded, the path layer's
    // cap, far beyond where Russian roulette ends every walk.
    const int max_depth = settings.max_depth < 0
                              ? kMaxPathVertices - 1
                              : std::min(settings.max_depth, kMaxPathVertices - 1);
    limits_ = {max_depth, subpath_rr_depth(settings.rr_depth)};
  }

  bool splats() const override { return true; }

  void sample(int, int, Rng& rng, DVec3&, TileOutput& out) override {
    if (limits_.max_vertices < 1) return;
    thread_local PathVertices light;
    generate_light_subpath(scene_, rng, limits_, light, &out.invalid);
    for (int s = std::max(1, settings_.shortest_path()); s <= int(light.size()); ++s) {
      const PathVertex& y = light[size_t(s - 1)];
      const PathVertex* y_previous = s >= 2 ? &light[size_t(s - 2)] : nullptr;
      const Vec2 u_lens = rng.uniform2();
      const std::optional<PathVertex> lens = y.is_environment()
                                                 ? sky_camera_vertex(scene_, y, u_lens)
                                                 : sample_camera_vertex(scene_, y, u_lens);
      if (!lens) continue;
      Rgb value =
          y.throughput * connect_vertices(scene_, y_previous, y, *lens, nullptr) * lens->throughput;
      if (is_black(value) || !out.invalid.keep(value)) continue;
      // Mitsuba's ptracer image is its splats alone, each through the whole filter: near
      // the image's edge the part of a footprint off the image is lost, not renormalised.
      scene_.camera().filter().splat_unrenormalised(
          lens->raster,
          [&](uint32_t target, float weight) { out.splats.add(target, value * weight); });
    }
  }

 private:
  const Scene& scene_;
  const RenderSettings& settings_;
  WalkLimits limits_;
};

class ParticleTracer final : public Integrator {
 public:
  std::string name() const override { return "ptracer"; }
  RenderResult render(const Scene& scene, const RenderSettings& settings,
                      ProgressReporter& progress) const override {
    ParticleTracerStep step(scene, settings);
    return PassRunner(scene, settings, progress, step).render();
  }
};

}  // namespace

std::unique_ptr<Integrator> make_particle_tracer() {
  return std::make_unique<ParticleTracer>();
}

}  // namespace emlt
