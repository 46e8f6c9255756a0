#include "emlt/integrators/erpt/erpt_integrator.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/film/fixed_point_film.h"
#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/mlt/bootstrap.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/integrators/mlt/mlt_step.h"
#include "emlt/integrators/mlt/normalisation_sums.h"
#include "emlt/mcmc/strategy_mix.h"
#include "emlt/path/path.h"
#include "emlt/run/pass_runner.h"
#include "emlt/scene/scene.h"

namespace emlt {

namespace {

// Mitsuba's ERPT runs Veach's perturbations and leaves the bidirectional mutation off: the
// seeds, not the chains, are to find the paths.
constexpr const char* kErptMix = "lens=1,caustic=1,multichain=1";
constexpr uint64_t kChainStream = 0xe4b7ull << 40;
// More threads than this share films (atomic additions), as the MCMC sweeper's.
constexpr int kMaxFilms = 16;

// b, the image's mean luminance over the paths the chains take: `samples` bootstrap samples
// in groups of 1,024 summed in order (the same on every rank and at any thread count). It
// only sets how many chains a seed starts, never what they deposit in expectation.
NormalisationSums mean_luminance(const Scene& scene, const BootstrapParams& p, uint64_t samples,
                                 int threads) {
  const uint64_t groups = (samples + 1023) / 1024;
  std::vector<NormalisationSums> sums(groups);
  tbb::task_arena(threads).execute([&] {
    tbb::parallel_for(uint64_t(0), groups, [&](uint64_t g) {
      const uint64_t first = 1024 * g, last = std::min(samples, first + 1024);
      bootstrap_sample_totals(scene, p, uint32_t(first), uint32_t(last),
                              [&](double x) { sums[g].add(x); });
    });
  });
  NormalisationSums total;
  for (const NormalisationSums& s : sums) total.add(s);
  return total;
}

class ErptStep final : public PixelSampleStep {
 public:
  ErptStep(const Scene& scene, const RenderSettings& settings, const StrategyMix& mix,
           const MutationContext& ctx, const BootstrapParams& seeds, double b, int threads,
           ErptOptions options)
      : options_(options),
        scene_(scene),
        settings_(settings),
        mix_(mix),
        ctx_(ctx),
        seeds_(seeds),
        b_(b),
        width_(scene.camera().width()),
        height_(scene.camera().height()),
        // Chains per pixel sample: --erpt-chains per pixel over the --spp budget (per pass
        // under a time budget alone), as Mitsuba's numChains over its sampleCount.
        chains_per_sample_(settings.erpt_chains / double(std::max(settings.spp, 1))),
        // A step deposits e = b / (c L) of energy (at the mean chain count); the films count
        // in units of e, as MLT's count in units of a step's weight.
        unit_(b > 0.0 ? b / (chains_per_sample_ * settings.erpt_chain_length) : 1.0),
        chain_seed_(derive_stream_seed(settings.seed, kChainStream)),
        films_(size_t(std::clamp(threads, 1, kMaxFilms)),
               FixedPointFilm(size_t(width_) * size_t(height_))),
        shared_(threads > kMaxFilms),
        stats_([n = mix.size()] { return std::vector<BlockCounter>(n); }) {}

  void sample(int x, int y, Rng& rng, DVec3&, TileOutput&) override {
    const Vec2 raster(float(x) + rng.uniform(), float(y) + rng.uniform());
    // The chains' own streams, keyed by two draws of the sample's, so the seed's draws stay
    // the bootstrap's order.
    const uint64_t key = (uint64_t(rng.next_u32()) << 32) | rng.next_u32();
    Rng decide = Rng::for_item(chain_seed_, key);
    const size_t thread = size_t(std::max(tbb::this_task_arena::current_thread_index(), 0));
    FixedPointFilm& film = films_[thread % films_.size()];
    const PixelFilter& filter = scene_.camera().filter();
    enumerate_sample_at(
        scene_, seeds_, rng, raster,
        [&](int s, int t, const Rgb& value, std::span<const PathVertex> light,
            std::span<const PathVertex> camera) {
          const DVec3 c(value);
          const double w = luminance(c);
          const Vec2 at = camera.front().raster;
          // Paths shorter than the chains take (the direct light, with --direct separate), a
          // light seen directly (one segment: Mitsuba's perturbations do not apply to it, so
          // its ERPT leaves such seeds where they are; chains would only spread the light's
          // image over its neighbours), and seeds whose joined path carries nothing after
          // all: deposited as BDPT found them.
          const auto deposit = [&] {
            const DVec3 units = c / unit_;
            if (filter.is_box()) {
              const int px = std::clamp(int(at.x), 0, width_ - 1),
                        py = std::clamp(int(at.y), 0, height_ - 1);
              film.add(size_t(py) * size_t(width_) + size_t(px), units, shared_);
            } else {
              filter.splat(at, [&](uint32_t pixel, float f) {
                film.add(pixel, units * double(f), shared_);
              });
            }
          };
          if (s + t - 1 < ctx_.min_edges) {
            deposit();
            return true;
          }
          if (!(b_ > 0.0)) return true;
          // Chains on average c w / b (at most the bound), their number rounded at random.
          const double unbounded = chains_per_sample_ * w / b_;
          double mean = unbounded;
          if (settings_.erpt_max_chains > 0.0) mean = std::min(mean, settings_.erpt_max_chains);
          const double u = decide.uniform_double();
          const int chains = int(std::floor((options_.chains_rounded_down ? 0.0 : u) + mean));
          if (chains == 0) return true;
          Path path;
          if (!join_subpaths(scene_, light, s, camera, t, path)) return true;
          recompute_densities(scene_, path);
          const DVec3 contribution = path_contribution(scene_, path);
          const double target = luminance(contribution);
          if (!(target > 0.0) || !std::isfinite(target)) {
            deposit();
            return true;
          }
          // Each step deposits w / (mean L): in units of e, 1 at the unbounded mean.
          const double scale = (w / ((options_.deposit_ignores_bound ? unbounded : mean) *
                                     settings_.erpt_chain_length)) /
                               unit_;
          const FilmSlot slot{film, nullptr, shared_, filter, scale};
          BlockOutput out{stats_.local(), {}};
          chains_started_.fetch_add(uint64_t(chains), std::memory_order_relaxed);
          const StrategyMask applicable = mix_.applicable(path, ctx_);
          for (int k = 0; k < chains; ++k) {
            MltChain chain;
            chain.current = path;
            chain.contribution = contribution;
            chain.target = target;
            chain.applicable = applicable;
            chain.rng = Rng::for_item(derive_stream_seed(chain_seed_, key),
                                      (uint64_t(s) << 40) | (uint64_t(t) << 20) | uint64_t(k));
            chain.sweep_left = uint64_t(settings_.erpt_chain_length);
            // A chain is part of its sample, which is never cut: run_chain's checks for a stop
            // (every 1,024 steps) only pause it.
            while (chain.sweep_left > 0)
              run_chain(chain, 0, mix_, ctx_, StepRules{}, out, slot, width_, height_);
            slot.splat(width_, height_, chain.current, chain.contribution, chain.target,
                       chain.carried);
          }
          return true;
        });
  }

  void add_own_film(Image& image, uint64_t samples) override {
    std::vector<int64_t> units;
    if (!FixedPointFilm::total_units(films_, units))
      throw Error("the ERPT film overflowed: too much energy deposited in one pixel");
    cluster::sum_to_root(units);
    if (samples == 0 || !cluster::is_root()) return;
    // Deposits are in units of e; a pixel sample's estimate is worth pixels / samples.
    const double scale =
        unit_ / FixedPointFilm::kUnitsPerValue * double(image.pixels.size()) / double(samples);
    for (size_t p = 0; p < image.pixels.size(); ++p)
      image.pixels[p] += Rgb(
          DVec3(double(units[3 * p]), double(units[3 * p + 1]), double(units[3 * p + 2])) * scale);
  }

  void save(StateWriter& out) const override {
    std::vector<int64_t> units;
    if (!FixedPointFilm::total_units(films_, units))
      throw Error("the ERPT film overflowed: too much energy deposited in one pixel");
    out.put_vector(units);
  }
  void load(StateReader& in) override {
    FixedPointFilm::load_units(films_,
                               in.get_vector<int64_t>(3 * size_t(width_) * size_t(height_)));
  }

  // What the chains did (this run's and this rank's; the counts do not depend on the thread
  // count, the acceptance sums' last bits may): how many started, their steps, and each
  // strategy's proposals and acceptance, into `stats` beside b.
  void add_chain_figures(const StrategyMix& mix, MltStatistics& stats) const {
    std::vector<StrategyStats> total(mix.size());
    for (const std::vector<BlockCounter>& local : stats_)
      for (size_t i = 0; i < local.size(); ++i) total[i].merge(local[i]);
    stats.chains = chains_started_.load();
    stats.mutations = stats.chains * uint64_t(settings_.erpt_chain_length);
    for (size_t i = 0; i < mix.size(); ++i) stats.strategy_names.push_back(mix.name(i));
    stats.strategies = std::move(total);
  }

 private:
  ErptOptions options_;
  const Scene& scene_;
  const RenderSettings& settings_;
  const StrategyMix& mix_;
  MutationContext ctx_;
  BootstrapParams seeds_;
  double b_;
  int width_, height_;
  double chains_per_sample_;
  double unit_;
  uint64_t chain_seed_;
  std::vector<FixedPointFilm> films_;
  bool shared_;
  // The strategies' counters, one set per thread (run_chain counts into them).
  tbb::enumerable_thread_specific<std::vector<BlockCounter>> stats_;
  std::atomic<uint64_t> chains_started_{0};
};

class Erpt final : public Integrator, public ChainStatisticsSource {
 public:
  explicit Erpt(ErptOptions options) : options_(options) {}
  std::string name() const override { return "erpt"; }
  RenderResult render(const Scene& scene, const RenderSettings& settings,
                      ProgressReporter& progress) const override {
    const StrategyMix mix =
        StrategyMix::parse(settings.mutations.empty() ? kErptMix : settings.mutations);
    const uint64_t pixels = uint64_t(scene.camera().width()) * uint64_t(scene.camera().height());
    MutationContext ctx{scene};
    // A light seen directly is never a chain's (ErptStep deposits it as its seed found it):
    // the chains' domain starts at two segments, so that none (a bidirectional mutation)
    // moves energy into it either.
    ctx.min_edges = settings.direct_separate ? 3 : std::max(2, settings.shortest_path());
    ctx.max_edges = settings.max_depth < 0 ? BidirectionalPathTracer::kUnlimitedDepth
                                           : std::min(settings.max_depth, kMaxPathVertices - 1);
    ctx.lens_max_radius = std::sqrt(0.05f * float(pixels) / kPi);
    ctx.manifold_prob_factor = settings.manifold_lambda;
  ctx.manifold_angle_change = settings.manifold_angle_change * (M_PI / 180.0);
    for (size_t i = 0; i < mix.size(); ++i) mix.strategy(i).prepare(ctx);
    const int threads =
        settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
    // The seeds: every strategy of a pixel sample, the shortest paths included; b over the
    // paths the chains take, from the bootstrap's stream.
    const BootstrapParams seeds =
        BootstrapParams::of(settings, settings.shortest_path(), ctx.max_edges, threads);
    const auto started = std::chrono::steady_clock::now();
    const NormalisationSums b =
        ctx.min_edges > ctx.max_edges
            ? NormalisationSums{}
            : mean_luminance(scene,
                             BootstrapParams::of(settings, ctx.min_edges, ctx.max_edges, threads),
                             uint64_t(std::max(settings.bootstrap_samples, 0)), threads);
    const double bootstrap_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    ErptStep step(scene, settings, mix, ctx, seeds, b.b(), threads, options_);
    RenderResult result = PassRunner(scene, settings, progress, step).render();
    stats_ = MltStatistics{};
    stats_.b = stats_.bootstrap_b = b.b();
    stats_.b_standard_error = b.error();
    stats_.b_largest_share = b.largest_share();
    stats_.b_samples = stats_.bootstrap_samples = b.samples;
    stats_.bootstrap_seconds = bootstrap_seconds;
    // The runner's time (the seeds' samples with their chains) and the luminance samples'.
    stats_.seconds = result.seconds + bootstrap_seconds;
    step.add_chain_figures(mix, stats_);
    return result;
  }
  // b and what the chains did: the seeds' chains only distribute their energy, so the chain
  // count and steps are figures of the run, not a budget; under MPI this rank's.
  const MltStatistics& chain_statistics() const override { return stats_; }

 private:
  ErptOptions options_;
  mutable MltStatistics stats_;
};

}  // namespace

std::unique_ptr<Integrator> make_erpt(ErptOptions options) {
  return std::make_unique<Erpt>(options);
}

const std::vector<RenderOption>& erpt_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> o = {
        real_option("--erpt-chains", &RenderSettings::erpt_chains, 0.0, true, 1e9,
                    "a positive number, at most a billion",
                    "erpt: chains started per pixel on average over the --spp budget (per "
                    "pixel sample under --time alone; Mitsuba's numChains; default 1)"),
        real_option("--erpt-max-chains", &RenderSettings::erpt_max_chains, 0.0, false, 1e6,
                    "a number from 0 (no bound) to a million",
                    "erpt: most chains a seed path starts (Mitsuba's maxChains; default 0, no "
                    "bound)"),
        whole_option("--erpt-chain-length", &RenderSettings::erpt_chain_length, 1, 1 << 24,
                     "a whole number from 1 to 2^24", "erpt: steps per chain (default 100)"),
    };
    apply_only_where(o, [](const RenderSettings& s) { return s.integrator == "erpt"; });
    return o;
  }();
  return options;
}

}  // namespace emlt
