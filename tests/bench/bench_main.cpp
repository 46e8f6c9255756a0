// Speed figures (not tests): Embree rays/s for coherent camera rays and incoherent bounce
// rays, and path-tracer samples/s, on the Cornell box at 256x256; MLT mutations/s per
// strategy mix on the Cornell box and the door-ajar scene (and multi-chain on cornell-glass,
// the only shipped scene of the three where it applies).
//   build/tests/emlt_bench                      (all threads)
//   build/tests/emlt_bench --benchmark_filter=PathTracer
#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <map>
#include <memory>
#include <mutex>

#include "emlt/core/rng.h"
#include "emlt/core/warp.h"
#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/integrators/path_tracer.h"
#include "emlt/integrators/registry.h"
#include "emlt/scene/loaders/loader.h"

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
        if (!scene.intersect(scene.camera().generate_ray(Vec2(x + 0.5f, y + 0.5f), Vec2(0.5f)),
                             hit))
          continue;
        // Cosine-distributed secondary rays: incoherent across neighbouring pixels.
        const Vec3 d = hit.shading.to_world(square_to_cosine_hemisphere(rng.uniform2()));
        SurfaceHit next;
        benchmark::DoNotOptimize(
            scene.intersect(spawn_ray(hit.position, hit.geometric_normal, d), next));
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

void PathTracerSamples(benchmark::State& state) {
  IntegratorSamples(state, PathTracer());
}
void BdptSamples(benchmark::State& state) {
  IntegratorSamples(state, BidirectionalPathTracer());
}

const Scene& shipped_scene_256(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Scene>> scenes;
  static std::mutex lock;
  const std::lock_guard guard(lock);
  auto& scene = scenes[name];
  if (!scene) {
    SceneDescription desc = load_scene_description(
        std::string(EMLT_SOURCE_DIR) + "/scenes/" + name + "/scene.json", {});
    desc.camera.width = desc.camera.height = 256;
    scene = Scene::build(std::move(desc));
  }
  return *scene;
}

// MLT at 256x256 with 16 mutations per pixel (1048576 mutations, 64 chains). "mutations/s"
// divides the mutations by the whole render's time, which includes a small bootstrap
// (10000 BDPT samples), a 1-spp direct image and allocating and summing the threads' films.
// "chain mutations/s" takes out the bootstrap and the direct pass (the render's own timing
// split, MltStatistics): the rate of the chains themselves, the figure docs/performance.md
// quotes. At 4 mutations per pixel the films' fixed cost was 8 % of the chains' time.
void MltMutations(benchmark::State& state, const std::string& scene_name, const std::string& mix,
                  const std::string& integrator_name) {
  const Scene& scene = shipped_scene_256(scene_name);
  RenderSettings settings;
  settings.threads = int(state.range(0));
  settings.progress = false;
  settings.mutations = mix;
  settings.mutations_per_pixel = 16;
  settings.chains = integrator_name == "emlt" ? 0 : 64;  // EMLT's chains are its ensembles
  settings.bootstrap_samples = 10000;
  settings.direct_spp = 1;
  ProgressReporter progress(false);
  uint64_t mutations = 0;
  double acceptance_sum = 0.0, proposed = 0.0, chain_seconds = 0.0;
  for (auto _ : state) {
    const auto integrator = make_integrator(integrator_name);
    const auto& mlt = dynamic_cast<const MltIntegrator&>(*integrator);
    mlt.render(scene, settings, progress);
    const MltStatistics& st = mlt.statistics();
    mutations += st.mutations;
    chain_seconds += st.seconds - st.direct_seconds - st.bootstrap_seconds - st.prepare_seconds;
    for (const auto& s : st.strategies) {
      acceptance_sum += s.acceptance_sum;
      proposed += double(s.proposed);
    }
    settings.seed++;
  }
  state.counters["mutations/s"] =
      benchmark::Counter(double(mutations), benchmark::Counter::kIsRate);
  state.counters["chain mutations/s"] =
      chain_seconds > 0.0 ? double(mutations) / chain_seconds : 0.0;
  state.counters["acceptance"] = proposed > 0.0 ? acceptance_sum / proposed : 0.0;
  state.counters["threads"] = settings.threads;
}

}  // namespace

BENCHMARK(CameraRays)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BounceRays)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(PathTracerSamples)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BdptSamples)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
#define EMLT_MLT_BENCH(name, scene, mix) EMLT_INTEGRATOR_BENCH(name, scene, mix, "mlt")
#define EMLT_INTEGRATOR_BENCH(name, scene, mix, integrator)                   \
  BENCHMARK_CAPTURE(MltMutations, name, std::string(scene), std::string(mix), \
                    std::string(integrator))                                  \
      ->Arg(1)                                                                \
      ->Arg(2)                                                                \
      ->Unit(benchmark::kMillisecond)                                         \
      ->UseRealTime()
EMLT_MLT_BENCH(cornell_bidir, "cornell-box", "bidir=1");
EMLT_MLT_BENCH(cornell_lens, "cornell-box", "lens=1");
EMLT_MLT_BENCH(cornell_caustic, "cornell-box", "caustic=1");
EMLT_MLT_BENCH(cornell_default_mix, "cornell-box", "bidir=3,lens=2,caustic=2,multichain=2");
EMLT_MLT_BENCH(door_bidir, "door-ajar", "bidir=1");
EMLT_MLT_BENCH(door_lens, "door-ajar", "lens=1");
EMLT_MLT_BENCH(door_caustic, "door-ajar", "caustic=1");
EMLT_MLT_BENCH(door_default_mix, "door-ajar", "bidir=3,lens=2,caustic=2,multichain=2");
EMLT_MLT_BENCH(glass_bidir_multichain, "cornell-glass", "bidir=1,multichain=4");
EMLT_MLT_BENCH(glass_default_mix, "cornell-glass", "bidir=3,lens=2,caustic=2,multichain=2");
// Ensemble MLT with its default mix (empty: the integrator's own) and the ablation presets.
EMLT_INTEGRATOR_BENCH(cornell_emlt, "cornell-box", "", "emlt");
EMLT_INTEGRATOR_BENCH(cornell_emlt_lin, "cornell-box", "emlt-lin", "emlt");
EMLT_INTEGRATOR_BENCH(cornell_emlt_ani, "cornell-box", "emlt-ani", "emlt");
EMLT_INTEGRATOR_BENCH(door_emlt, "door-ajar", "", "emlt");
BENCHMARK_MAIN();
