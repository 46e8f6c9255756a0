#include "emlt/integrators/mis_alpha_map.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>

#include "emlt/integrators/pixel_renderer.h"
#include "emlt/sampling/mixture_direct_estimator.h"

namespace emlt {

namespace {

// Keeps the pre-pass's streams apart from the render's (seed, pixel) streams.
constexpr uint64_t kPrePassStream = 0x6d69732d616c7068ull;

}  // namespace

std::vector<float> preprocess_mis_alpha(const Scene& scene, const RenderSettings& settings) {
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  std::vector<float> alpha(size_t(width) * size_t(height), 0.5f);
  const int per_ray = 2 * std::max(settings.direct_samples, 1);
  const int rays = std::max(1, (settings.mis_alpha_samples + per_ray - 1) / per_ray);
  const int threads =
      settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena(threads).execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < width; ++x) {
          const uint64_t pixel = uint64_t(y) * uint64_t(width) + uint64_t(x);
          const uint64_t stream = derive_stream_seed(settings.seed ^ kPrePassStream, pixel);
          SecondOrderAlpha moments;
          for (int k = 0; k < rays; ++k) {
            Rng rng(stream, uint64_t(k));
            const Ray ray = pixel_camera_ray(camera, x, y, rng);
            SurfaceHit hit;
            if (!scene.intersect(ray, hit)) continue;
            const Vec3 wo = -ray.direction;
            if (!scene.sides_agree(hit.geometric_normal, wo, hit.shading.to_local(wo).z)) continue;
            estimate_direct_pilot(scene, hit, wo, rng, per_ray, &moments);
          }
          alpha[size_t(pixel)] = float(moments.alpha(settings.mis_alpha_clamp));
        }
    });
  });
  return alpha;
}

}  // namespace emlt
