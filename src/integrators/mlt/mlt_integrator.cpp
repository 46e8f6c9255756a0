#include "emlt/integrators/mlt/mlt_integrator.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdio>
#include <optional>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/mlt/bootstrap.h"
#include "emlt/integrators/mlt/mcmc_run.h"
#include "emlt/integrators/mlt/mlt_chains.h"
#include "emlt/path/path_state.h"
#include "emlt/run/render_control.h"

namespace emlt {

namespace {

constexpr uint64_t kChainStream = 0xc4a1ull << 40;
constexpr uint64_t kSeedStream = 0x5eedull << 40;

}  // namespace

// Many short chains: each starts from a bootstrap path resampled in proportion to its
// contribution, so there is no start-up bias to run off, and more chains cover the image
// more evenly than a few long ones that linger in bright regions. Measured on the door scene
// (64 x 64, 256 mutations per pixel, seed 1, direct light at 2048 spp): MSE 1.10e-4 with 20
// chains (the old default, mutations / 50000), 5.7e-5 with 1024, 4.6e-5 with 4096, 3.5e-5
// with 16384; on the Cornell box at 64 mutations per pixel 16 -> 4096 chains gave 2.17e-4 ->
// 1.95e-4. About 64 steps per chain, at most 16384 chains (EMLT's ensembles are as large).
// Manifold exploration is the other way round: its chains cross the caustics that Veach's
// perturbations leave them stuck on, and many short chains only keep the seed pool's noise.
// memlt on the caustic pool (Mitsuba's file, 3 seeds, MSE against the reference; 12 seeds'
// variance at 128 x 128): 64 x 64 at 1,024 mutations per pixel 1.9e-4 / 1.6e-4 / 1.5e-3 with
// 1,024 / 4,096 / 16,384 chains; at 4,096 1.5e-4 / 1.2e-4 / 4.8e-4; 128 x 128 at 128 per
// pixel 3.4e-3 / 5.1e-3 / 6.4e-3 with 512 / 2,048 / 16,384 (docs/memlt.md). About 4,096
// steps per chain fits all three (kMemltStepsPerChain).
int MltIntegrator::default_chain_count(uint64_t mutations, uint64_t steps_per_chain) {
  return int(std::clamp<uint64_t>(mutations / steps_per_chain, 16, 16384));
}

RenderResult MltIntegrator::render(const Scene& scene, const RenderSettings& settings,
                                   ProgressReporter& progress) const {
  // The clock (with the runs before a resume), the checkpoint state and the direct pass.
  McmcRun run(scene, settings);
  const uint64_t pixels = run.pixels();
  const std::shared_ptr<const StrategyMix> mix_holder =
      options_.mix ? options_.mix
                   : std::make_shared<const StrategyMix>(StrategyMix::parse(
                         settings.mutations.empty() ? options_.default_mix : settings.mutations));
  const StrategyMix& mix = *mix_holder;
  stats_ = MltStatistics{};
  for (size_t i = 0; i < mix.size(); ++i) stats_.strategy_names.push_back(mix.name(i));
  stats_.strategies.assign(mix.size(), StrategyStats{});

  MutationContext ctx{scene};
  ctx.min_edges = settings.direct_separate ? 3 : settings.shortest_path();
  ctx.max_edges = settings.max_depth < 0 ? BidirectionalPathTracer::kUnlimitedDepth
                                         : std::min(settings.max_depth, kMaxPathVertices - 1);
  ctx.lens_max_radius = std::sqrt(0.05f * float(pixels) / kPi);
  ctx.field_cone = settings.gamlt_field_cone;
  ctx.manifold_prob_factor = settings.manifold_lambda;
  ctx.manifold_angle_change = settings.manifold_angle_change * (M_PI / 180.0);
  ctx.cone_cell_fraction = settings.gamlt_field_cone ? 0.0 : settings.gamlt_cone_cells;
  // Strategies defer the costly factors of their ratios only for the two stages (run_chain):
  // otherwise the whole ratio is needed for every proposal with f(y) > 0, and the strategy
  // computes it where x's ranges are at hand (deferring it cost the default about 1.5 % of
  // its instructions for the f(y) = 0 proposals it spared, which are few).
  ctx.may_defer = settings.gamlt_delayed_acceptance;
  // Timed apart: the chains' rate leaves it out (MltStatistics::prepare_seconds).
  const double prepare_start = run.elapsed();
  for (size_t i = 0; i < mix.size(); ++i) mix.strategy(i).prepare(ctx);
  stats_.prepare_seconds = run.elapsed() - prepare_start;

  // A resumed render's chains (mcmc_run.h).
  std::string& chain_section = run.chain_section();

  RenderResult result = run.black_result();
  if (ctx.min_edges > ctx.max_edges) {
    run.end_without_chains(result, stats_);
    return result;
  }

  const int threads = ChainSweeper::thread_count(settings);
  const BootstrapParams bp = BootstrapParams::of(settings, ctx.min_edges, ctx.max_edges, threads);
  const bool timed = settings.time_limit_s > 0.0;
  const uint64_t budget =
      uint64_t(std::llround(std::max(settings.mutations_per_pixel, 0.0) * double(pixels)));
  const uint64_t planned =
      timed ? (settings.mutations_per_pixel > 0 ? budget : UINT64_MAX) : budget;
  // Ensemble mode (ensemble_schedule.h): the chains are the two ensembles.
  std::unique_ptr<EnsembleSchedule> ensemble =
      options_.ensemble
          ? std::make_unique<EnsembleSchedule>(scene, settings, options_.ensemble_params, pixels)
          : nullptr;
  const uint64_t ensemble_size = ensemble ? ensemble->size() : 0;
  int chain_count = ensemble              ? int(2 * ensemble_size)
                    : settings.chains > 0 ? settings.chains
                                          : default_chain_count(timed ? pixels * 16 : budget,
                                                                options_.steps_per_chain);

  const PathCodec codec(scene);
  NormalisationPass normalisation(scene, bp, settings.normalisation_rate);
  std::optional<StateReader> chain_in;
  std::vector<MltChain> chains;
  if (!chain_section.empty()) {
    // Resumed: the bootstrap's results and the chains as they were. The chain count is the
    // checkpoint's (the default depends on the budget, which a resumed run may extend).
    chain_in.emplace(chain_section);
    chains = MltChains::load_chains(*chain_in, codec, stats_, 2 * ensemble_size);
    chain_count = int(chains.size());
    // Which strategies apply follows from the path (and is checked that way).
    for (MltChain& chain : chains) chain.applicable = mix.applicable(chain.current, ctx);
  } else {
    const double bootstrap_start = run.elapsed();
    Bootstrap bootstrap = run_bootstrap(scene, bp);
    if (settings.bootstrap_grows && !bootstrap.interrupted && !bootstrap.empty()) {
      // The ranks of an MPI render agree on the larger time-bound figure (each timed its own
      // first round), so that every rank grows the same pool.
      std::vector<uint64_t> by_time{timed ? bootstrap_time_cap(bootstrap.samples,
                                                               settings.time_limit_s,
                                                               run.elapsed() - bootstrap_start)
                                          : UINT64_MAX};
      cluster::max_everywhere(by_time);
      const uint64_t by_time_cap = by_time[0];
      const uint64_t grown = grown_bootstrap_samples(
          bootstrap.samples, bootstrap.effective_candidates(), uint64_t(chain_count),
          bootstrap_growth_cap(bootstrap.samples, bootstrap.candidates.size(), planned,
                               by_time_cap));
      grow_bootstrap(scene, bp, grown, bootstrap);
    }
    if (run.stopped_in_bootstrap(bootstrap.interrupted, result, stats_)) return result;
    stats_.b = stats_.bootstrap_b = bootstrap.b;
    stats_.b_standard_error = bootstrap.standard_error;
    stats_.bootstrap_samples = bootstrap.samples;
    if (bootstrap.empty()) {
      stats_.bootstrap_seconds = run.elapsed() - bootstrap_start;
      run.end_without_chains(result, stats_,
                             "no bootstrap path carries light; the MLT part of the image is black");
      return result;
    }
    // (In --stats: on Veach's door the pool is worth some 8,800 candidates, and 16,384
    // default chains of 2,300 steps gave 2.5x the variance of 1,024 chains; docs/performance.md.)
    stats_.bootstrap_effective_candidates = bootstrap.effective_candidates();
    normalisation.start(bootstrap);
    // Seeds: each chain resamples the bootstrap pool from its own stream (in EMLT, both
    // ensembles come from the one pool, §3.4).
    // In parallel: each chain has its own stream, so the order does not matter (serial, the
    // rebuilds took a quarter of the bootstrap's time at 2 threads).
    chains.resize(size_t(chain_count));
    tbb::task_arena(threads).execute([&] {
      tbb::parallel_for(0, chain_count, [&](int c) {
        MltChain& chain = chains[size_t(c)];
        Rng seed_rng =
            Rng::for_item(derive_stream_seed(settings.start_seed(), kSeedStream), uint64_t(c));
        for (int attempt = 0; attempt < 16 && !(chain.target > 0.0); ++attempt) {
          const auto path = rebuild_candidate(
              scene, bp, bootstrap.candidates[bootstrap.choose(seed_rng.uniform_double())]);
          if (!path) continue;
          chain.current = *path;
          chain.contribution = path_contribution(scene, chain.current);
          chain.target = luminance(chain.contribution);
        }
        chain.rng = Rng::for_item(derive_stream_seed(settings.seed, kChainStream), uint64_t(c));
        chain.applicable = mix.applicable(chain.current, ctx);
      });
    });
    stats_.bootstrap_seconds = run.elapsed() - bootstrap_start;
  }

  MltSetup setup{scene,
                 settings,
                 mix,
                 ctx,
                 StepRules{options_.ignore_selection_probability, settings.mlt_expected_values,
                           options_.drop_rejected_steps},
                 planned,
                 std::move(ensemble),
                 std::move(normalisation)};
  MltChains mlt(std::move(setup), std::move(chains), run, progress, stats_,
                chain_in ? &*chain_in : nullptr);
  chain_in.reset();
  chain_section.clear();
  result = mlt.render(options_.name);
  run.direct_statistics(stats_);
  stats_.seconds = result.seconds;
  return result;
}

}  // namespace emlt
