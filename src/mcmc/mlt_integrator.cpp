#include "emlt/mcmc/mlt_integrator.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "emlt/mcmc/bootstrap.h"
#include "emlt/render/bdpt.h"
#include "emlt/render/direct_integrator.h"
#include "emlt/render/snapshot.h"

namespace emlt {

namespace {

constexpr uint64_t kChainStream = 0xc4a1ull << 40;
constexpr uint64_t kSeedStream = 0x5eedull << 40;
constexpr int kMaxBlocks = 16;

double luminance(const DVec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

struct Chain {
  Path current;
  DVec3 contribution{0.0};  // F(x)
  double target = 0.0;      // f*(x)
  double carried = 0.0;     // expected-value weight not yet splatted for x
  std::vector<uint8_t> applicable;           // which strategies apply to `current`
  std::vector<uint8_t> proposal_applicable;  // the same for the latest proposal (reused buffer)
  Rng rng;
  std::vector<StrategyStats> stats;
};

// The film pixel a path lands in.
size_t film_index(const Path& path, int width, int height) {
  const Vec2 raster = path.raster();
  const int x = std::clamp(int(raster.x), 0, width - 1), y = std::clamp(int(raster.y), 0, height - 1);
  return size_t(y) * size_t(width) + size_t(x);
}

// Adds weight * F / f* at the path's pixel.
void splat(std::vector<DVec3>& film, int width, int height, const Path& path,
           const DVec3& contribution, double target, double weight) {
  if (!(weight > 0.0) || !(target > 0.0)) return;
  film[film_index(path, width, height)] += contribution * (weight / target);
}

void run_chain(Chain& chain, uint64_t steps, const StrategyMix& mix, const MutationContext& ctx,
               bool ignore_selection, std::vector<DVec3>& film, int width, int height) {
  for (uint64_t step = 0; step < steps; ++step) {
    double p_forward = 0.0;
    const int chosen = mix.choose(chain.applicable, chain.rng.uniform(), &p_forward);
    for (size_t i = 0; i < mix.size(); ++i)
      if (!chain.applicable[i]) ++chain.stats[i].not_applicable;
    if (chosen < 0) {  // nothing applies: the path stays
      chain.carried += 1.0;
      continue;
    }
    StrategyStats& stats = chain.stats[size_t(chosen)];
    ++stats.proposed;

    double acceptance = 0.0;
    auto proposal = mix.strategy(size_t(chosen)).propose(chain.current, chain.rng, ctx);
    DVec3 contribution(0.0);
    double target = 0.0;
    if (proposal) {
      // Proposals land anywhere on the image, so the splat below would usually wait on
      // memory (a block's film is larger than the caches): start loading the pixel now,
      // while the contribution is evaluated.
      __builtin_prefetch(&film[film_index(proposal->path, width, height)], 1);
      contribution = path_contribution(ctx.scene, proposal->path);
      target = luminance(contribution);
      if (target > 0.0 && std::isfinite(target)) {
        mix.applicable(proposal->path, ctx, chain.proposal_applicable);
        const double p_reverse =
            ignore_selection ? p_forward : mix.selection_probability(size_t(chosen), chain.proposal_applicable);
        const double ratio = target / chain.target * std::exp(proposal->log_reverse_over_forward) *
                             (p_reverse / p_forward);
        acceptance = std::isfinite(ratio) ? std::clamp(ratio, 0.0, 1.0) : (ratio > 0.0 ? 1.0 : 0.0);
      }
    }
    if (!proposal || !(target > 0.0)) ++stats.failed;
    stats.acceptance_sum += acceptance;

    // Expected values: the proposal's share now, the current path's when it is left.
    chain.carried += 1.0 - acceptance;
    if (acceptance > 0.0) splat(film, width, height, proposal->path, contribution, target, acceptance);
    if (chain.rng.uniform() < acceptance) {
      splat(film, width, height, chain.current, chain.contribution, chain.target, chain.carried);
      chain.current = std::move(proposal->path);
      chain.contribution = contribution;
      chain.target = target;
      std::swap(chain.applicable, chain.proposal_applicable);
      chain.carried = 0.0;
      ++stats.accepted;
    }
  }
}

}  // namespace

int MltIntegrator::default_chain_count(uint64_t mutations) {
  return int(std::clamp<uint64_t>(mutations / 50000, 16, 1024));
}

RenderResult MltIntegrator::render(const Scene& scene, const RenderSettings& settings,
                                   ProgressReporter& progress) const {
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  const std::shared_ptr<const StrategyMix> mix_holder =
      options_.mix ? options_.mix
                   : std::make_shared<const StrategyMix>(StrategyMix::parse(
                         settings.mutations.empty() ? options_.default_mix : settings.mutations));
  const StrategyMix& mix = *mix_holder;
  stats_ = MltStatistics{};
  for (size_t i = 0; i < mix.size(); ++i) stats_.strategy_names.push_back(mix.name(i));
  stats_.strategies.assign(mix.size(), StrategyStats{});

  MutationContext ctx{scene};
  ctx.min_edges = settings.direct_separate ? 3 : 1;
  ctx.max_edges = settings.max_depth < 0 ? BidirectionalPathTracer::kUnlimitedDepth
                                         : std::min(settings.max_depth, kMaxPathVertices - 1);
  ctx.lens_max_radius = std::sqrt(0.05f * float(pixels) / kPi);

  RenderResult result;
  result.image = Image(width, height);
  // Paths of one and two segments (emitters seen directly, direct light) from the direct
  // integrator, as Mitsuba does by default; the chains then never visit them.
  if (settings.direct_separate) {
    RenderSettings direct = settings;
    const bool time_only = settings.time_limit_s > 0.0 && !(settings.mutations_per_pixel > 0.0);
    direct.spp = settings.direct_spp > 0 ? settings.direct_spp
                 : time_only             ? 16
                                         : std::max(1, int(std::ceil(settings.mutations_per_pixel)));
    direct.time_limit_s = 0.0;
    direct.snapshots = nullptr;  // the log follows the chains, not this pass
    ProgressReporter quiet(false);
    result.image = DirectIntegrator().render(scene, direct, quiet).image;
    result.invalid_samples = 0;
  }
  if (ctx.min_edges > ctx.max_edges) {
    result.seconds = elapsed();
    return result;
  }

  const int threads = settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  BootstrapParams bp;
  bp.seed = settings.seed;
  bp.samples = settings.bootstrap_samples;
  bp.min_edges = ctx.min_edges;
  bp.max_edges = ctx.max_edges;
  bp.rr_depth = settings.rr_depth;
  bp.mis = settings.mis;
  bp.threads = threads;
  const Bootstrap bootstrap = run_bootstrap(scene, bp);
  stats_.b = bootstrap.b;
  stats_.b_standard_error = bootstrap.standard_error;
  stats_.bootstrap_samples = bootstrap.samples;
  if (bootstrap.empty()) {
    std::fprintf(stderr, "emlt: warning: no bootstrap path carries light; the MLT part of the image is black\n");
    result.seconds = elapsed();
    return result;
  }

  const bool timed = settings.time_limit_s > 0.0;
  const uint64_t budget = uint64_t(std::llround(std::max(settings.mutations_per_pixel, 0.0) * double(pixels)));
  const uint64_t planned = timed ? (settings.mutations_per_pixel > 0 ? budget : UINT64_MAX) : budget;
  const int chain_count = settings.chains > 0 ? settings.chains
                                              : default_chain_count(timed ? pixels * 16 : budget);
  const int blocks = std::min(chain_count, kMaxBlocks);

  // Seeds: each chain resamples the bootstrap pool from its own stream.
  std::vector<Chain> chains;
  chains.resize(size_t(chain_count));
  for (int c = 0; c < chain_count; ++c) {
    Chain& chain = chains[size_t(c)];
    Rng seed_rng = Rng::for_item(derive_stream_seed(settings.seed, kSeedStream), uint64_t(c));
    for (int attempt = 0; attempt < 16 && !(chain.target > 0.0); ++attempt) {
      const auto path = rebuild_candidate(scene, bp, bootstrap.candidates[bootstrap.choose(seed_rng.uniform_double())]);
      if (!path) continue;
      chain.current = *path;
      chain.contribution = path_contribution(scene, chain.current);
      chain.target = luminance(chain.contribution);
    }
    chain.rng = Rng::for_item(derive_stream_seed(settings.seed, kChainStream), uint64_t(c));
    chain.applicable = mix.applicable(chain.current, ctx);
    chain.stats.assign(mix.size(), StrategyStats{});
  }

  std::vector<std::vector<DVec3>> films(size_t(blocks), std::vector<DVec3>(pixels, DVec3(0.0)));
  const auto block_first_chain = [&](int block) { return int(int64_t(chain_count) * block / blocks); };

  // The image after `mutations` steps: the direct part, plus the blocks' films summed in
  // order and each chain's weight not yet splatted (added to a copy: the chains go on
  // untouched), scaled so the image's mean luminance is b.
  uint64_t live = 0;  // chains with a seed (all, in practice)
  for (const Chain& chain : chains) live += chain.target > 0.0;
  const Image direct_image = result.image;
  const auto compose = [&](uint64_t mutations_done) {
    std::vector<DVec3> total(pixels, DVec3(0.0));
    for (const auto& film : films)
      for (uint64_t p = 0; p < pixels; ++p) total[p] += film[p];
    for (const Chain& chain : chains)
      splat(total, width, height, chain.current, chain.contribution, chain.target, chain.carried);
    const double splatted = double(mutations_done) * double(live) / double(chain_count);
    const double scale = splatted > 0.0 ? double(pixels) * bootstrap.b / splatted : 0.0;
    Image image = direct_image;
    for (uint64_t p = 0; p < pixels; ++p) image.pixels[p] += Rgb(total[p] * scale);
    return image;
  };
  const auto acceptance_so_far = [&] {
    std::vector<StrategyAcceptance> out;
    for (size_t i = 0; i < mix.size(); ++i) {
      StrategyStats merged;
      for (const Chain& chain : chains) merged.merge(chain.stats[i]);
      out.push_back({mix.name(i), merged.mean_acceptance()});
    }
    return out;
  };
  double snapshot_seconds = 0.0;
  const auto take_snapshot = [&](uint64_t mutations_done) {
    const auto begin = std::chrono::steady_clock::now();
    settings.snapshots->snapshot(double(mutations_done) / double(pixels), elapsed() - snapshot_seconds,
                                 compose(mutations_done), acceptance_so_far());
    snapshot_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  };

  tbb::task_arena arena(threads);
  progress.start("mlt", timed ? 0 : planned, settings.time_limit_s);
  // Rounds of one mutation per pixel: checkpoints (powers of two in mutations per pixel)
  // fall on round ends, and the time budget is checked between rounds.
  const uint64_t round_size = std::max<uint64_t>(pixels, uint64_t(chain_count));
  uint64_t done = 0;
  while (done < planned) {
    const uint64_t this_round = std::min(round_size, planned - done);
    arena.execute([&] {
      tbb::parallel_for(0, blocks, [&](int block) {
        for (int c = block_first_chain(block); c < block_first_chain(block + 1); ++c) {
          if (!(chains[size_t(c)].target > 0.0)) continue;
          const uint64_t steps = this_round / uint64_t(chain_count) +
                                 (uint64_t(c) < this_round % uint64_t(chain_count) ? 1 : 0);
          run_chain(chains[size_t(c)], steps, mix, ctx, options_.ignore_selection_probability,
                    films[size_t(block)], width, height);
          progress.advance(steps);
        }
      });
    });
    done += this_round;
    const bool checkpoint = done % pixels == 0 && is_checkpoint(done / pixels);
    if (settings.snapshots && checkpoint) take_snapshot(done);
    if (timed && elapsed() - snapshot_seconds >= settings.time_limit_s) break;
  }
  if (settings.snapshots && !(done % pixels == 0 && is_checkpoint(done / pixels))) take_snapshot(done);
  progress.finish();

  result.image = compose(done);
  for (const Chain& chain : chains)
    for (size_t i = 0; i < mix.size(); ++i) stats_.strategies[i].merge(chain.stats[i]);
  stats_.chains = uint64_t(chain_count);
  stats_.mutations = done;
  stats_.seconds = elapsed() - snapshot_seconds;
  result.seconds = stats_.seconds;
  result.samples = done;
  result.samples_per_pixel = int(std::llround(double(done) / double(pixels)));
  return result;
}

}  // namespace emlt
