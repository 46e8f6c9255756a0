// Embree's own incoherent ray rate on a scene: the bound that no integrator of that scene
// can beat with one closest-hit query per path segment (performance suite, bench/run.sh).
//
//   emlt_ray_rate SCENE [--threads N] [--seconds S] [--bvh-only] [-D name=value ...]
//
// First records the rays a path tracer would trace: per pixel, the camera ray, then up to
// three cosine-distributed bounces from the surfaces hit (incoherent across neighbouring
// queries, as in a real render). Then times the closest-hit query alone on that buffer
// (Scene::closest_hit: rtcIntersect1 plus the few analytic spheres Scene tests outside the
// BVH; no hit reconstruction, no shading) and, separately, Scene::occluded (rtcOccluded1
// and those spheres) on shadow rays from each hit
// towards a point on the scene's bounding sphere; both on N threads, repeated for about S
// seconds. On a scene of a few dozen triangles, which Scene tests one by one instead of
// through the BVH (emlt/scene/direct_triangles.h), these are the rates of that test;
// --bvh-only times Embree's BVH there too. Prints one line of key=value pairs for the
// suite to read.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "emlt/core/error.h"
#include "emlt/core/rng.h"
#include "emlt/core/warp.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"

using namespace emlt;

namespace {

constexpr int kBounces = 3;

struct RayBuffers {
  std::vector<Ray> intersect;  // camera rays and bounces, in path order
  std::vector<Ray> occlusion;  // one shadow ray per surface hit
};

RayBuffers record_rays(const Scene& scene) {
  const int width = scene.camera().width(), height = scene.camera().height();
  std::vector<RayBuffers> rows(static_cast<size_t>(height));
  tbb::parallel_for(0, height, [&](int y) {
    RayBuffers& out = rows[size_t(y)];
    Rng rng = Rng::for_item(1, uint64_t(y));
    for (int x = 0; x < width; ++x) {
      Ray ray = scene.camera().generate_ray(Vec2(x, y) + rng.uniform2(), rng.uniform2());
      for (int bounce = 0; bounce <= kBounces; ++bounce) {
        out.intersect.push_back(ray);
        SurfaceHit hit;
        if (!scene.intersect(ray, hit)) break;
        Vec3 n = hit.geometric_normal;
        if (glm::dot(n, ray.direction) > 0.0f) n = -n;
        const Vec3 target = scene.bounds_center() +
                            scene.bounds_radius() * square_to_uniform_sphere(rng.uniform2());
        Ray shadow = spawn_ray(hit.position, n, glm::normalize(target - hit.position));
        shadow.tmax = glm::length(target - hit.position);
        out.occlusion.push_back(shadow);
        const Frame frame(n);
        ray =
            spawn_ray(hit.position, n, frame.to_world(square_to_cosine_hemisphere(rng.uniform2())));
      }
    }
  });
  RayBuffers all;
  for (const RayBuffers& row : rows) {
    all.intersect.insert(all.intersect.end(), row.intersect.begin(), row.intersect.end());
    all.occlusion.insert(all.occlusion.end(), row.occlusion.begin(), row.occlusion.end());
  }
  return all;
}

// Rays per second of `query` over `rays`, repeated for at least `seconds`, on `threads`.
template <typename Query>
double rate(const std::vector<Ray>& rays, int threads, double seconds, Query query) {
  tbb::task_arena arena(threads);
  std::atomic<uint64_t> hits{0};
  uint64_t traced = 0;
  const auto start = std::chrono::steady_clock::now();
  double elapsed = 0.0;
  do {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 4096), [&](const auto& range) {
        uint64_t n = 0;
        for (size_t i = range.begin(); i != range.end(); ++i) n += query(rays[i]);
        hits += n;
      });
    });
    traced += rays.size();
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  } while (elapsed < seconds);
  return double(traced) / elapsed;
}

int usage() {
  std::fprintf(stderr,
               "usage: emlt_ray_rate SCENE [--threads N] [--seconds S] [--bvh-only] "
               "[-D name=value ...]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path;
  int threads = 0;
  double seconds = 2.0;
  bool bvh_only = false;
  SceneDefines defines;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--threads" || arg == "--seconds" || arg == "-D") && i + 1 >= argc) return usage();
    if (arg == "--threads") {
      threads = std::atoi(argv[++i]);
    } else if (arg == "--seconds") {
      seconds = std::atof(argv[++i]);
    } else if (arg == "--bvh-only") {
      bvh_only = true;
    } else if (arg == "-D") {
      const std::string define = argv[++i];
      const size_t eq = define.find('=');
      if (eq == std::string::npos) return usage();
      defines[define.substr(0, eq)] = define.substr(eq + 1);
    } else if (path.empty() && !arg.empty() && arg[0] != '-') {
      path = arg;
    } else {
      return usage();
    }
  }
  if (path.empty() || threads < 0 || !(seconds > 0.0)) return usage();
  if (threads == 0) threads = tbb::this_task_arena::max_concurrency();
  try {
    const std::unique_ptr<Scene> scene = Scene::build(
        load_scene_description(path, defines), SceneBuildOptions{.direct_triangles = !bvh_only});
    const RayBuffers rays = record_rays(*scene);
    // Scene's own ray queries, without hit reconstruction or shading: Embree's BVH plus
    // the few analytic spheres that Scene tests outside it.
    const Scene& queries = *scene;
    const double closest = rate(rays.intersect, threads, seconds, [&queries](const Ray& ray) {
      RTCRayHit query;
      return queries.closest_hit(ray, query) ? 1 : 0;
    });
    const double shadow = rate(rays.occlusion, threads, seconds, [&queries](const Ray& ray) {
      return queries.occluded(ray) ? 1 : 0;
    });
    std::printf(
        "scene=%s threads=%d triangles=%zu rays=%zu intersect_rays_per_s=%.0f "
        "occluded_rays_per_s=%.0f\n",
        path.c_str(), threads, scene->stats().triangles, rays.intersect.size(), closest, shadow);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "emlt_ray_rate: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
