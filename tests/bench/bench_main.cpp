// Speed figures (not tests): Embree rays/s for coherent camera rays and incoherent bounce
// rays, and path-tracer samples/s, on the Cornell box at 256x256.
//   build/tests/emlt_bench                      (all threads)
//   build/tests/emlt_bench --benchmark_filter=PathTracer
#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <memory>

#include "emlt/core/rng.h"
#include "emlt/core/warp.h"
#include "emlt/render/bdpt.h"
#include "emlt/render/path_tracer.h"
#include "emlt/scene/loader.h"

using namespace emlt;

namespace {

const Scene& cornell_box() {
  static const std::unique_ptr<Scene> scene = [] {
    SceneDescription desc =
        load_scene_description(std::string(EMLT_SOURCE_DIR) + "/scenes/cornell-box/scene.json", {});
    desc.camera.width = desc.camera.height = 256;
    return Scene::build(std::move(desc));
  }();
  return *scene;
}

// Runs body(row, rng) for every image row in parallel on `threads` threads; returns rays.
template <typename Body>
uint64_t for_rows(int threads, Body body) {
  const Scene& scene = cornell_box();
  tbb::task_arena arena(threads);
  std::atomic<uint64_t> rays{0};
  arena.execute([&] {
    tbb::parallel_for(0, scene.camera().height(), [&](int y) {
      Rng rng(uint64_t(y), 1);
      rays += body(scene, y, rng);
    });
  });
  return rays;
}

void CameraRays(benchmark::State& state) {
  const int threads = int(state.range(0));
  uint64_t total = 0;
  for (auto _ : state) {
    total += for_rows(threads, [](const Scene& scene, int y, Rng& rng) {
      uint64_t n = 0;
      for (int x = 0; x < scene.camera().width(); ++x) {
        SurfaceHit hit;
        const Ray ray = scene.camera().generate_ray(Vec2(x + 0.5f, y + 0.5f), rng.uniform2());
        benchmark::DoNotOptimize(scene.intersect(ray, hit));
        ++n;
      }
      return n;
    });
  }
  state.counters["rays/s"] = benchmark::Counter(double(total), benchmark::Counter::kIsRate);
  state.counters["threads"] = threads;
}

void BounceRays(benchmark::State& state) {
  const int threads = int(state.range(0));
  uint64_t total = 0;
  for (auto _ : state) {
    total += for_rows(threads, [](const Scene& scene, int y, Rng& rng) {
      uint64_t n = 0;
      for (int x = 0; x < scene.camera().width(); ++x) {
        SurfaceHit hit;
        if (!scene.intersect(scene.camera().generate_ray(Vec2(x + 0.5f, y + 0.5f), Vec2(0.5f)), hit))
          continue;
        // Cosine-distributed secondary rays: incoherent across neighbouring pixels.
        const Vec3 d = hit.shading.to_world(square_to_cosine_hemisphere(rng.uniform2()));
        SurfaceHit next;
        benchmark::DoNotOptimize(scene.intersect(spawn_ray(hit.position, hit.geometric_normal, d), next));
        ++n;
      }
      return n;
    });
  }
  state.counters["rays/s"] = benchmark::Counter(double(total), benchmark::Counter::kIsRate);
  state.counters["threads"] = threads;
}

// One camera sample per pixel per iteration; for BDPT a sample is a camera subpath, a
// light subpath and all their connections, so the two rates compare cost per sample.
void IntegratorSamples(benchmark::State& state, const Integrator& integrator) {
  RenderSettings settings;
  settings.spp = 1;
  settings.threads = int(state.range(0));
  settings.progress = false;
  ProgressReporter progress(false);
  uint64_t samples = 0;
  for (auto _ : state) {
    const RenderResult r = integrator.render(cornell_box(), settings, progress);
    samples += r.samples;
    settings.seed++;
  }
  state.counters["samples/s"] = benchmark::Counter(double(samples), benchmark::Counter::kIsRate);
  state.counters["threads"] = settings.threads;
}

void PathTracerSamples(benchmark::State& state) { IntegratorSamples(state, PathTracer()); }
void BdptSamples(benchmark::State& state) { IntegratorSamples(state, BidirectionalPathTracer()); }

}  // namespace

BENCHMARK(CameraRays)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BounceRays)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(PathTracerSamples)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BdptSamples)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
