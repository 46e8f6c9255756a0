#include "emlt/integrators/bdpt.h"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <optional>

#include "emlt/core/cluster.h"
#include "emlt/core/rng.h"
#include "emlt/path/connection.h"
#include "emlt/path/path_density.h"
#include "emlt/path/random_walk.h"
#include "emlt/run/pass_runner.h"

namespace emlt {

namespace {

// Strategy images: paths of n = s + t vertices, n = 2 .. kMaxStrategyImageDepth + 1, and
// s = 0 .. n - 1, numbered n by n.
int strategy_image_index(int s, int t) {
  const int n = s + t;
  if (t < 1 || n < 2 || n - 1 > BidirectionalPathTracer::kMaxStrategyImageDepth) return -1;
  return (n - 1) * n / 2 - 1 + s;
}
int strategy_image_count() {
  const int n = BidirectionalPathTracer::kMaxStrategyImageDepth + 1;
  return n * (n + 1) / 2 - 1;
}

// Everything one pixel sample needs; the vectors are reused by a thread's samples.
struct SampleScratch {
  PathVertices light, camera;
  VertexDensity densities[kMaxPathVertices];
  float filter_weight = 1.0f;  // the pixel sample's filter weight, for camera-side strategies
};

// One pixel sample of BDPT for the pass runner; with strategy images, it also keeps each
// strategy's camera-side sums per pixel.
class BdptStep final : public PixelSampleStep {
 public:
  BdptStep(const Scene& scene, const RenderSettings& settings, const BdptOptions& options,
           int strategies)
      : scene_(scene),
        settings_(settings),
        options_(options),
        strategy_images_(strategies > 0),
        strategies_(strategies),
        pixels_(size_t(scene.camera().width()) * size_t(scene.camera().height())),
        strategy_sums_(size_t(strategies) * pixels_, DVec3(0.0)) {
    max_depth_ = settings.max_depth < 0 ? BidirectionalPathTracer::kUnlimitedDepth
                                        : std::min(settings.max_depth, kMaxPathVertices - 1);
    // A path of max_depth segments has max_depth + 1 vertices: s = 0 needs them all on the
    // camera side, t = 1 needs max_depth on the light side.
    camera_limits_ = {max_depth_ + 1, subpath_rr_depth(settings.rr_depth)};
    light_limits_ = {max_depth_, subpath_rr_depth(settings.rr_depth)};
  }

  bool splats() const override { return true; }
  int film_layers() const override { return strategies_; }
  void save(StateWriter& out) const override { out.put_vector(strategy_sums_); }
  void load(StateReader& in) override {
    strategy_sums_ = in.get_vector<DVec3>(strategy_sums_.size());
  }
  const std::vector<DVec3>& strategy_sums() const { return strategy_sums_; }

  // Camera-side contributions go to `pixel` (and the pixel's strategy sums), light-tracing
  // splats to the tile's list.
  void sample(int x, int y, Rng& rng, DVec3& pixel, TileOutput& out) override {
    // Same stream and first draws as the path tracer's.
    const Vec2 jitter = rng.uniform2();
    const Vec2 u_lens = rng.uniform2();
    const FilterSample pixel_sample = scene_.camera().filter().sample(x, y, jitter);
    const Vec2 raster = pixel_sample.raster;
    thread_local SampleScratch scratch;
    scratch.filter_weight = pixel_sample.weight;
    DVec3* strategy_pixel =
        strategy_images_ ? &strategy_sums_[size_t(y) * size_t(scene_.camera().width()) + size_t(x)]
                         : nullptr;
    auto& camera = scratch.camera;
    auto& light = scratch.light;
    generate_camera_subpath(scene_, rng, raster, u_lens, camera_limits_, camera, &out.invalid);
    generate_light_subpath(scene_, rng, light_limits_, light, &out.invalid);

    for (int t = 1; t <= int(camera.size()); ++t) {
      if (options_.only_t >= 1 && t != options_.only_t) continue;
      for (int s = 0; s <= int(light.size()); ++s) {
        const int segments = s + t - 1;
        if (segments < settings_.shortest_path()) continue;
        if (segments > max_depth_) break;
        if (options_.only_s >= 0 && s != options_.only_s) continue;
        evaluate_strategy(rng, s, t, scratch, pixel, strategy_pixel, out);
      }
    }
  }

 private:
  // strategy_pixel: the pixel's sum of strategy 0; strategy i's lies i * pixels after it.
  void evaluate_strategy(Rng& rng, int s, int t, SampleScratch& scratch, DVec3& pixel,
                         DVec3* strategy_pixel, TileOutput& out) const {
    const auto& camera = scratch.camera;
    const auto& light = scratch.light;
    Rgb contribution(0.0f);
    // The lens vertex sampled for t = 1 (empty otherwise: most strategies need none).
    std::optional<PathVertex> lens;
    std::span<const PathVertex> camera_side(camera);
    if (s == 0) {
      // The camera subpath found an emitter (or the sky) at its last vertex.
      const PathVertex& z = camera[size_t(t - 1)];
      if (!z.is_emitter()) return;
      contribution = z.throughput * vertex_factor(scene_, z, nullptr, &camera[size_t(t - 2)]);
    } else {
      const PathVertex& y = light[size_t(s - 1)];
      const PathVertex* y_previous = s >= 2 ? &light[size_t(s - 2)] : nullptr;
      if (t == 1) {
        lens = sample_camera_vertex(scene_, y, rng.uniform2());
        if (!lens) return;
        camera_side = std::span<const PathVertex>(&*lens, 1);
        contribution = y.throughput * connect_vertices(scene_, y_previous, y, *lens, nullptr) *
                       lens->throughput;
      } else {
        const PathVertex& z = camera[size_t(t - 1)];
        contribution = y.throughput *
                       connect_vertices(scene_, y_previous, y, z, &camera[size_t(t - 2)]) *
                       z.throughput;
      }
    }
    if (is_black(contribution)) return;

    double weight = 1.0;
    if (options_.mis) {
      const std::span<VertexDensity> densities(scratch.densities, size_t(s + t));
      connection_densities(scene_, light, s, camera_side, t, densities);
      weight = mis_weight(densities, s, settings_.mis);
    }
    Rgb value = contribution * float(weight);
    if (!out.invalid.keep(value) || is_black(value)) return;

    const int strategy = strategy_images_ ? strategy_image_index(s, t) : -1;
    if (t == 1) {
      // Light tracing: the contribution lands in every pixel whose filter covers it.
      scene_.camera().filter().splat(lens->raster, [&](uint32_t target, float weight) {
        out.splats.add(target, value * weight, strategy);
      });
      return;
    }
    const DVec3 weighted = DVec3(value) * double(scratch.filter_weight);
    pixel += weighted;
    if (strategy >= 0) strategy_pixel[size_t(strategy) * pixels_] += weighted;
  }

  const Scene& scene_;
  const RenderSettings& settings_;
  const BdptOptions& options_;
  bool strategy_images_;
  int strategies_;
  size_t pixels_;
  // Strategy i's camera-side sum of pixel p at i * pixels + p.
  std::vector<DVec3> strategy_sums_;
  int max_depth_ = 0;
  WalkLimits camera_limits_, light_limits_;
};

void write_strategy_images(const std::string& directory, int width, int height,
                           const std::vector<DVec3>& camera_sums, const SplatFilm& film,
                           const std::vector<int32_t>& counts, double splat_scale) {
  std::filesystem::create_directories(directory);
  const size_t pixels = size_t(width) * size_t(height);
  for (int n = 2; n <= BidirectionalPathTracer::kMaxStrategyImageDepth + 1; ++n) {
    for (int s = 0; s < n; ++s) {
      const int index = strategy_image_index(s, n - s);
      Image image(width, height);
      for (size_t p = 0; p < pixels; ++p) {
        const double camera_scale = counts[p] > 0 ? 1.0 / counts[p] : 0.0;
        image.pixels[p] = Rgb(camera_sums[size_t(index) * pixels + p] * camera_scale +
                              film.layer(index)[p] * splat_scale);
      }
      const std::string name = fmt::format("s{}_t{}.exr", s, n - s);
      write_image((std::filesystem::path(directory) / name).string(), image);
    }
  }
}

}  // namespace

RenderResult BidirectionalPathTracer::render(const Scene& scene, const RenderSettings& settings,
                                             ProgressReporter& progress) const {
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  const bool strategy_images = !settings.bdpt_strategies_dir.empty();
  BdptStep step(scene, settings, options_, strategy_images ? strategy_image_count() : 0);
  PassRunner runner(scene, settings, progress, step);
  RenderResult result = runner.render();
  if (strategy_images) {
    const std::vector<DVec3>& sums = step.strategy_sums();
    std::vector<double> strategy_totals(3 * sums.size());
    for (size_t i = 0; i < sums.size(); ++i)
      for (int c = 0; c < 3; ++c) strategy_totals[3 * i + size_t(c)] = sums[i][c];
    cluster::sum_to_root(strategy_totals);
    const PixelRenderState::Totals totals = runner.state().totals();
    if (cluster::is_root()) {
      std::vector<DVec3> strategy_sums(sums.size());
      for (size_t i = 0; i < sums.size(); ++i)
        strategy_sums[i] =
            DVec3(strategy_totals[3 * i], strategy_totals[3 * i + 1], strategy_totals[3 * i + 2]);
      write_strategy_images(settings.bdpt_strategies_dir, width, height, strategy_sums,
                            runner.film(), totals.counts, runner.splat_scale());
    }
  }
  return result;
}

const std::vector<RenderOption>& bdpt_options() {
  static const std::vector<RenderOption> options = [] {
    RenderOption strategies =
        path_option("--bdpt-strategies", &RenderSettings::bdpt_strategies_dir,
                    "bdpt: also write each strategy's MIS-weighted image (s<s>_t<t>.exr) here");
    // Whether there were strategy images to continue, not where they go.
    strategies.recorded = [](const RenderSettings& s) {
      return std::string(s.bdpt_strategies_dir.empty() ? "(none)" : "(a folder)");
    };
    return std::vector<RenderOption>{strategies};
  }();
  return options;
}

}  // namespace emlt
