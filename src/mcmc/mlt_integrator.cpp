#include "emlt/mcmc/mlt_integrator.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <optional>
#include <span>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/mcmc/bootstrap.h"
#include "emlt/mcmc/delayed_acceptance.h"
#include "emlt/mcmc/fixed_point_film.h"
#include "emlt/mcmc/mcmc_run.h"
#include "emlt/path/path_state.h"
#include "emlt/render/bdpt.h"
#include "emlt/render/image.h"
#include "emlt/render/interruption.h"
#include "emlt/render/pixel_renderer.h"
#include "emlt/render/render_control.h"
#include "emlt/render/snapshot.h"

namespace emlt {

namespace {

constexpr uint64_t kChainStream = 0xc4a1ull << 40;
constexpr uint64_t kSeedStream = 0x5eedull << 40;
constexpr int kMaxBlocks = 256;
constexpr int kMaxFilms = 16;
// The phase a checkpoint falls in.

double luminance(const DVec3& c) {
  return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

struct Chain {
  Path current;
  DVec3 contribution{0.0};      // F(x)
  double target = 0.0;          // f*(x)
  double carried = 0.0;         // expected-value weight not yet splatted for x
  StrategyMask applicable = 0;  // which strategies apply to `current`
  Rng rng;
  uint64_t steps_taken = 0;  // keys EMLT's choice of guides (ensemble_guides.h)
  uint64_t sweep_left = 0;   // steps still to take in the sweep under way
  bool moved = false;        // accepted a proposal since packed for the other ranks (EMLT, MPI)
};

// What one block of chains counts: its strategies' statistics. Blocks are a fixed partition
// of the chains, so the counters sum to the same bits on any thread count; kept per block
// rather than per chain because a chain visited for a single step (EMLT) would miss the
// cache on its own counters. Up to 256 blocks, so that with 16 threads each takes 16 per
// sweep and the last ones leave cores idle only briefly (greedy scheduling of measured block
// times: 0.95 of the ideal at 16 threads with 64 blocks, 0.99 with 256; docs/performance.md,
// "To 16 threads").
struct BlockOutput {
  // Each on its own cache lines: blocks run on different cores.
  struct alignas(64) Counters : StrategyStats {};
  std::vector<Counters> stats;
  AlphaTally alpha;  // the α of the block's guided linear steps (EMLT)
};

// Asks for a path's vertices ahead of use: EMLT visits each of its many chains for a single
// step, and the next chain's path is a separate allocation the hardware cannot guess.
void prefetch_path(const Path& path) {
  const char* data = reinterpret_cast<const char*>(path.vertices.data());
  const size_t bytes = path.vertices.size() * sizeof(PathVertex);
  for (size_t offset = 0; offset < bytes; offset += 64) __builtin_prefetch(data + offset);
}

// EMLT_MPI_PROFILE=1 (docs/scaling.md): every rank prints where its chains' loop spent its
// time: taking steps (wall time, and the calling thread's CPU time, which falls short of it
// when the rank was not running), building Y's guides, waiting at the per-sweep agreement
// (for the slowest rank, mostly), and EMLT's exchange of moved paths ("pack": joining what
// the blocks packed as their chains took their steps; MPI's allgather; unpacking the other
// ranks' paths).
struct SweepProfile {
  bool enabled = std::getenv("EMLT_MPI_PROFILE") != nullptr;
  double steps = 0.0, steps_cpu = 0.0, guides = 0.0, agreement = 0.0, pack = 0.0, gather = 0.0,
         unpack = 0.0;
  uint64_t bytes_sent = 0;
  static double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  static double thread_cpu() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
  }
  void print() const {
    if (!enabled) return;
    std::fprintf(stderr,
                 "emlt: profile rank %d: steps %.2f s (cpu %.2f s), guides %.2f s, agreement "
                 "%.2f s, exchange %.2f s (pack %.2f, allgather %.2f, unpack %.2f; %.0f MB "
                 "sent)\n",
                 cluster::rank(), steps, steps_cpu, guides, agreement, pack + gather + unpack, pack,
                 gather, unpack, double(bytes_sent) / 1e6);
  }
};

// The film pixel a path lands in.
size_t film_index(const Path& path, int width, int height) {
  const Vec2 raster = path.raster();
  const int x = std::clamp(int(raster.x), 0, width - 1),
            y = std::clamp(int(raster.y), 0, height - 1);
  return size_t(y) * size_t(width) + size_t(x);
}

// Adds weight * F / f* at the path's pixel, or spread over the pixels whose
// reconstruction filter covers its raster position.
void splat(std::vector<DVec3>& film, int width, int height, const PixelFilter& filter,
           const Vec2& raster, const DVec3& contribution, double target, double weight) {
  if (!(weight > 0.0) || !(target > 0.0)) return;
  const DVec3 value = contribution * (weight / target);
  if (filter.is_box()) {
    const int x = std::clamp(int(raster.x), 0, width - 1),
              y = std::clamp(int(raster.y), 0, height - 1);
    film[size_t(y) * size_t(width) + size_t(x)] += value;
  } else {
    filter.splat(raster, [&](uint32_t pixel, float w) { film[pixel] += value * double(w); });
  }
}

// What a composed image needs of a chain besides the films: where its current path lands,
// its contribution and target, and its weight not yet splatted. Under MPI only the chain's
// rank has them right; the others hold zeros, so a sum over ranks is exact (cluster.h).
constexpr size_t kCarriedFields = 7;
void put_carried(std::vector<double>& out, size_t chain, const Vec2& raster,
                 const DVec3& contribution, double target, double carried) {
  double* f = &out[kCarriedFields * chain];
  f[0] = raster.x, f[1] = raster.y, f[2] = contribution.x, f[3] = contribution.y;
  f[4] = contribution.z, f[5] = target, f[6] = carried;
}

// The film a chain splats into: its thread's (shared by several threads when there are more
// threads than films); likewise, when requested, the film of the image-plane moves of its
// proposals per pixel of the current path (sum dx^2, sum dy^2, count) for --aniso-map.
struct FilmSlot {
  FixedPointFilm& film;
  FixedPointFilm* moves;
  bool shared;
  const PixelFilter& filter;
  // Out of line so that a profile of the chains (bench/suite.py, callgrind) can tell
  // splatting from the driver's bookkeeping; one call per splat, below 1 % of a mutation.
  [[gnu::noinline]] void splat(int width, int height, const Path& path, const DVec3& contribution,
                               double target, double weight) const {
    if (!(weight > 0.0) || !(target > 0.0)) return;
    const DVec3 value = contribution * (weight / target);
    if (filter.is_box()) {
      film.add(film_index(path, width, height), value, shared);
      return;
    }
    filter.splat(path.raster(),
                 [&](uint32_t pixel, float w) { film.add(pixel, value * double(w), shared); });
  }
};

// Takes the chain's remaining steps of the sweep (chain.sweep_left), or returns early, with
// every step it took complete, when an interruption is requested; returns the steps taken.
// How a step scores: with expected values (the proposal gets a, the current path 1 - a) or,
// as the chains of the original MLT papers, the state after the step with weight 1.
struct StepRules {
  bool ignore_selection = false;
  bool expected_values = true;
  bool drop_rejected_steps = false;  // an injected bug (MltOptions)
};

uint64_t run_chain(Chain& chain, uint64_t chain_index, const StrategyMix& mix, MutationContext ctx,
                   const StepRules& rules, BlockOutput& out, const FilmSlot& film, int width,
                   int height) {
  ctx.chain = chain_index;
  // Steps taken with the current applicability, credited to the strategies that did not
  // apply whenever it changes (one loop per accepted move instead of one per step).
  uint64_t steps_with_mask = 0;
  const auto count_not_applicable = [&] {
    for (size_t i = 0; i < mix.size(); ++i)
      if (!((chain.applicable >> i) & 1u)) out.stats[i].not_applicable += steps_with_mask;
    steps_with_mask = 0;
  };
  uint64_t step = 0;
  for (; chain.sweep_left > 0; ++step) {
    // Every 1024 steps (about a millisecond): a stop is seen well within a second.
    if ((step & 1023) == 1023 && interruption::requested()) break;
    --chain.sweep_left;
    ctx.step = chain.steps_taken++;
    double p_forward = 0.0;
    const int chosen = mix.choose(chain.applicable, chain.rng.uniform(), &p_forward);
    ++steps_with_mask;
    if (chosen < 0) {  // nothing applies: the path stays
      chain.carried += 1.0;
      continue;
    }
    StrategyStats& stats = out.stats[size_t(chosen)];
    ++stats.proposed;

    // The proposal's expected-value weight: its acceptance probability, or under delayed
    // acceptance 1{first stage passed}·a2, whose expectation that is (delayed_acceptance.h).
    double acceptance = 0.0;
    double accept_below = 0.0;  // the step's uniform accepts the proposal below this
    const Mutation& strategy = mix.strategy(size_t(chosen));
    auto proposal = strategy.propose(chain.current, chain.rng, ctx);
    if (proposal && proposal->fallback) ++stats.fallbacks;
    if (proposal && proposal->alpha >= 0.0) out.alpha.add(proposal->alpha);
    if (proposal && film.moves) {
      const Vec2 move = proposal->path.raster() - chain.current.raster();
      film.moves->add(film_index(chain.current, width, height),
                      DVec3(double(move.x) * move.x, double(move.y) * move.y, 1.0), film.shared);
    }
    DVec3 contribution(0.0);
    double target = 0.0;
    StrategyMask proposal_applicable = 0;
    bool two_stages = false;
    double first_ratio = 0.0;  // the whole ratio, or the first stage's with two stages
    if (proposal) {
      // Proposals land anywhere on the image, so the splat below would usually wait on
      // memory (a film is larger than the caches): start loading the pixel now, while the
      // contribution is evaluated.
      film.film.prefetch(film_index(proposal->path, width, height));
      contribution = path_contribution(ctx.scene, proposal->path);
      target = luminance(contribution);
      if (target > 0.0 && std::isfinite(target)) {
        proposal_applicable = mix.applicable(proposal->path, ctx);
        const double p_reverse =
            rules.ignore_selection ? p_forward
                                   : mix.selection_probability(size_t(chosen), proposal_applicable);
        // A deferred factor (only under delayed acceptance, ctx.may_defer) is evaluated only
        // after the first stage has passed (below).
        two_stages = proposal->deferred;
        first_ratio = target / chain.target * std::exp(proposal->log_reverse_over_forward) *
                      (p_reverse / p_forward);
        acceptance = acceptance_probability(first_ratio);
      }
    }
    // Nothing draws from the chain's stream after the proposal, so this is the number the
    // step has always used, drawn before the splats since the second stage needs it.
    const double u = chain.rng.uniform();
    if (two_stages) {
      const TwoStageDecision d = two_stage_decision(first_ratio, u, [&] {
        return strategy.deferred_log_ratio(chain.current, *proposal, ctx);
      });
      acceptance = d.weight;
      accept_below = d.accept_below;
    } else {
      accept_below = acceptance;
    }
    if (!proposal || !(target > 0.0)) ++stats.failed;
    stats.acceptance_sum += acceptance;

    // Expected values: the proposal's share now, the current path's when it is left. Without
    // them, the state after the step gets the step's whole weight (carried to the proposal
    // when it is accepted).
    if (rules.expected_values) {
      chain.carried += 1.0 - acceptance;
      if (acceptance > 0.0)
        film.splat(width, height, proposal->path, contribution, target, acceptance);
    }
    if (u < accept_below) {
      film.splat(width, height, chain.current, chain.contribution, chain.target, chain.carried);
      chain.current = std::move(proposal->path);
      chain.moved = true;
      chain.contribution = contribution;
      chain.target = target;
      if (proposal_applicable != chain.applicable) count_not_applicable();
      chain.applicable = proposal_applicable;
      chain.carried = rules.expected_values ? 0.0 : 1.0;
      ++stats.accepted;
    } else if (!rules.expected_values && !rules.drop_rejected_steps) {
      chain.carried += 1.0;
    }
  }
  count_not_applicable();
  return step;
}

// The EMLT paper's Figure 12: the predominant image-plane direction of the proposals made
// from each pixel. Red: mostly horizontal, green: mostly vertical, yellow: isotropic; black
// where no proposal moved.
void write_move_map(const std::string& path, std::span<const FixedPointFilm> moves, int width,
                    int height) {
  Image map(width, height);
  bool in_range = true;
  for (const FixedPointFilm& film : moves) in_range &= !film.overflowed();
  for (size_t p = 0; p < map.pixels.size(); ++p) {
    DVec3 sum(0.0);
    if (!in_range || !FixedPointFilm::total(moves, p, sum))
      throw Error("the --aniso-map tallies overflowed: too many proposals per pixel");
    const double total = sum.x + sum.y;
    if (!(total > 0.0)) continue;
    const double horizontal = sum.x / total;
    map.pixels[p] = Rgb(float(std::min(1.0, 2.0 * horizontal)),
                        float(std::min(1.0, 2.0 * (1.0 - horizontal))), 0.0f);
  }
  write_image(path, map);
}

}  // namespace

// Many short chains: each starts from a bootstrap path resampled in proportion to its
// contribution, so there is no start-up bias to run off, and more chains cover the image
// more evenly than a few long ones that linger in bright regions. Measured on the door scene
// (64 x 64, 256 mutations per pixel, seed 1, direct light at 2048 spp): MSE 1.10e-4 with 20
// chains (the old default, mutations / 50000), 5.7e-5 with 1024, 4.6e-5 with 4096, 3.5e-5
// with 16384; on the Cornell box at 64 mutations per pixel 16 -> 4096 chains gave 2.17e-4 ->
// 1.95e-4. About 64 steps per chain, at most 16384 chains (EMLT's ensembles are as large).
int MltIntegrator::default_chain_count(uint64_t mutations) {
  return int(std::clamp<uint64_t>(mutations / 64, 16, 16384));
}

RenderResult MltIntegrator::render(const Scene& scene, const RenderSettings& settings,
                                   ProgressReporter& progress) const {
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  // The clock (with the runs before a resume), the checkpoint state and the direct pass.
  McmcRun run(settings, width, height);
  const auto elapsed = [&run] { return run.elapsed(); };
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
  // Strategies defer the costly factors of their ratios only for the two stages (run_chain):
  // otherwise the whole ratio is needed for every proposal with f(y) > 0, and the strategy
  // computes it where x's ranges are at hand (deferring it cost the default about 1.5 % of
  // its instructions for the f(y) = 0 proposals it spared, which are few).
  ctx.may_defer = settings.gamlt_delayed_acceptance;
  // Timed apart: the chains' rate leaves it out (MltStatistics::prepare_seconds).
  const double prepare_start = elapsed();
  for (size_t i = 0; i < mix.size(); ++i) mix.strategy(i).prepare(ctx);
  stats_.prepare_seconds = elapsed() - prepare_start;

  // Checkpoints (render_control.h, mcmc_run.h).
  RenderControl* control = run.control();
  std::string& chain_section = run.chain_section();

  RenderResult result;
  result.image = Image(width, height);
  // The chains then never visit the direct pass's paths.
  if (!run.direct_pass(scene, result, stats_)) return result;
  if (ctx.min_edges > ctx.max_edges) {
    run.finish_before_chains();
    result.seconds = elapsed();
    return result;
  }

  const int threads =
      settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  BootstrapParams bp;
  bp.seed = settings.start_seed();
  bp.samples = settings.bootstrap_samples;
  bp.min_edges = ctx.min_edges;
  bp.max_edges = ctx.max_edges;
  bp.rr_depth = settings.rr_depth;
  bp.mis = settings.mis;
  bp.threads = threads;
  const bool timed = settings.time_limit_s > 0.0;
  const uint64_t budget =
      uint64_t(std::llround(std::max(settings.mutations_per_pixel, 0.0) * double(pixels)));
  const uint64_t planned =
      timed ? (settings.mutations_per_pixel > 0 ? budget : UINT64_MAX) : budget;
  // Ensemble mode: |X| = |Y| = E and `it` steps per path between swaps (paper §3.4). The
  // paper's E = 16384 with it = floor(W H / 2E) assumes images of at least 2E pixels; on
  // smaller ones E shrinks to W H / 2 so that every path still moves once per half-sweep.
  const bool ensemble = options_.ensemble;
  const uint64_t ensemble_size = !ensemble ? 0
                                 : settings.ensemble_size > 0
                                     ? uint64_t(settings.ensemble_size)
                                     : std::clamp<uint64_t>(pixels / 2, 1, 16384);
  const uint64_t iterations = !ensemble ? 0
                              : settings.ensemble_iterations > 0
                                  ? uint64_t(settings.ensemble_iterations)
                                  : std::max<uint64_t>(1, pixels / (2 * ensemble_size));
  int chain_count = ensemble              ? int(2 * ensemble_size)
                    : settings.chains > 0 ? settings.chains
                                          : default_chain_count(timed ? pixels * 16 : budget);

  const PathCodec codec(scene);
  std::optional<StateReader> chain_in;
  double b = 0.0;
  std::vector<Chain> chains;
  if (!chain_section.empty()) {
    // Resumed: the bootstrap's results and the chains as they were. The chain count is the
    // checkpoint's (the default depends on the budget, which a resumed run may extend).
    chain_in.emplace(chain_section);
    StateReader& in = *chain_in;
    stats_.b = in.get<double>();
    b = stats_.b;
    stats_.b_standard_error = in.get<double>();
    stats_.bootstrap_samples = in.get<uint64_t>();
    stats_.bootstrap_seconds = in.get<double>();
    const uint64_t saved_count = in.get<uint64_t>();
    if (saved_count == 0 || saved_count > (uint64_t(1) << 20) ||
        (ensemble && saved_count != uint64_t(chain_count)))
      throw StateError("the saved chains do not fit this render (" + std::to_string(saved_count) +
                       " chains)");
    chain_count = int(saved_count);
    chains.resize(size_t(chain_count));
    for (Chain& chain : chains) {
      chain.current = codec.load(in);
      chain.contribution = in.get<DVec3>();
      chain.target = in.get<double>();
      chain.carried = in.get<double>();
      chain.rng = Rng::restore(in.get<Rng::State>());
      chain.steps_taken = in.get<uint64_t>();
      chain.sweep_left = in.get<uint64_t>();
      // F(x) is a colour, non-negative: the film turns splats into integers assuming so.
      const auto colour = [](double c) { return std::isfinite(c) && c >= 0.0; };
      if (!std::isfinite(chain.target) || chain.target < 0.0 || !std::isfinite(chain.carried) ||
          chain.carried < 0.0 || !colour(chain.contribution.x) || !colour(chain.contribution.y) ||
          !colour(chain.contribution.z) ||
          (chain.target > 0.0 && chain.current.vertices.empty()))
        throw StateError("a saved chain is inconsistent");
      // Which strategies apply follows from the path (and is checked that way).
      chain.applicable = mix.applicable(chain.current, ctx);
    }
  } else {
    const double bootstrap_start = elapsed();
    Bootstrap bootstrap = run_bootstrap(scene, bp);
    if (settings.bootstrap_grows && !bootstrap.interrupted && !bootstrap.empty()) {
      // The ranks of an MPI render agree on the larger time-bound figure (each timed its own
      // first round), so that every rank grows the same pool.
      std::vector<uint64_t> by_time{timed ? bootstrap_time_cap(bootstrap.samples,
                                                               settings.time_limit_s,
                                                               elapsed() - bootstrap_start)
                                          : UINT64_MAX};
      cluster::max_everywhere(by_time);
      const uint64_t by_time_cap = by_time[0];
      const uint64_t grown = grown_bootstrap_samples(
          bootstrap.samples, bootstrap.effective_candidates(), uint64_t(chain_count),
          bootstrap_growth_cap(bootstrap.samples, bootstrap.candidates.size(), planned,
                               by_time_cap));
      grow_bootstrap(scene, bp, grown, bootstrap);
    }
    // Every rank knows whether any rank's bootstrap was cut short (bootstrap.cpp); the
    // agreement makes every rank's stop request and checkpoint the same.
    interruption::agree(bootstrap.interrupted);
    if (bootstrap.interrupted) {
      // Nothing of the bootstrap is kept: a resumed render runs it again, to the same bits.
      run.pause_before_chains();
      result.interrupted = true;
      result.stopped_in = "the bootstrap";
      result.seconds = stats_.seconds = elapsed();
      return result;
    }
    b = stats_.b = bootstrap.b;
    stats_.b_standard_error = bootstrap.standard_error;
    stats_.bootstrap_samples = bootstrap.samples;
    if (bootstrap.empty()) {
      stats_.bootstrap_seconds = elapsed() - bootstrap_start;
      // Every rank holds the same gathered pool (bootstrap.cpp); one warning is enough.
      if (cluster::is_root())
        std::fprintf(
            stderr,
            "emlt: warning: no bootstrap path carries light; the MLT part of the image is black\n");
      run.finish_before_chains();
      result.seconds = elapsed();
      return result;
    }
    // (In --stats: on Veach's door the pool is worth some 8,800 candidates, and 16,384
    // default chains of 2,300 steps gave 2.5x the variance of 1,024 chains; docs/performance.md.)
    stats_.bootstrap_effective_candidates = bootstrap.effective_candidates();
    // Seeds: each chain resamples the bootstrap pool from its own stream (in EMLT, both
    // ensembles come from the one pool, §3.4).
    // In parallel: each chain has its own stream, so the order does not matter (serial, the
    // rebuilds took a quarter of the bootstrap's time at 2 threads).
    chains.resize(size_t(chain_count));
    tbb::task_arena(threads).execute([&] {
      tbb::parallel_for(0, chain_count, [&](int c) {
        Chain& chain = chains[size_t(c)];
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
    stats_.bootstrap_seconds = elapsed() - bootstrap_start;
  }

  const bool record_moves = !settings.aniso_map_path.empty();
  std::vector<BlockOutput> blocks(
      size_t(std::min(ensemble ? int(ensemble_size) : chain_count, kMaxBlocks)));
  // One film per thread, up to kMaxFilms of them; beyond that threads share films.
  std::vector<FixedPointFilm> films(size_t(std::min(threads, kMaxFilms)), FixedPointFilm(pixels));
  const bool shared_films = size_t(threads) > films.size();
  // Moves are tallied in pixels^2 at 2^-8: a pixel holds 3.6e16, some 1e10 proposals that
  // cross a 4K image from it.
  std::vector<FixedPointFilm> move_films(record_moves ? films.size() : 0,
                                         FixedPointFilm(pixels, 256.0));
  for (BlockOutput& block : blocks) block.stats.assign(mix.size(), BlockOutput::Counters{});
  // Under MPI each rank runs a contiguous share of the blocks (of each half, in EMLT); a
  // chain is in one block, so it is moved by one rank only.
  // (Not a structured binding: clang 14, the fuzz build's compiler, cannot capture one.)
  const std::pair<uint64_t, uint64_t> owned_blocks = cluster::share(blocks.size());
  const uint64_t first_owned_block = owned_blocks.first, last_owned_block = owned_blocks.second;
  const auto owns_block = [&](uint64_t block) {
    return block >= first_owned_block && block < last_owned_block;
  };
  // A sweep's chains (all of them in MLT, a half-ensemble in EMLT) fall in its blocks as
  // chain j of `count` in block b when count b / B <= j < count (b + 1) / B (B blocks, the
  // split of the sweep loop below), so a rank's blocks hold one range of them.
  const uint64_t sweep_chains = ensemble ? ensemble_size : uint64_t(chain_count);
  const uint64_t first_owned_chain = sweep_chains * first_owned_block / blocks.size(),
                 end_owned_chain = sweep_chains * last_owned_block / blocks.size();

  // The sweep under way: chains [first, first + count) take `size` steps between them
  // (chain.sweep_left each), `done_before` counting the mutations before it.
  struct Sweep {
    uint8_t active = 0;
    uint64_t first = 0, count = 0, size = 0, done_before = 0;
  } sweep;
  uint64_t done = 0, next_checkpoint = 1, half = 0, timed_rounds = 1;
  double alpha_sum = 0.0;
  const bool resumed = chain_in.has_value();
  if (chain_in) {
    StateReader& in = *chain_in;
    for (BlockOutput& block : blocks)
      for (StrategyStats& stats : block.stats) stats = in.get<StrategyStats>();
    const std::vector<int64_t> units = in.get_vector<int64_t>(3 * pixels);
    FixedPointFilm::load_units(films, units);
    const std::vector<int64_t> move_units = in.get_vector<int64_t>(record_moves ? 3 * pixels : 0);
    if (record_moves) FixedPointFilm::load_units(move_films, move_units);
    sweep.active = in.get<uint8_t>();
    sweep.first = in.get<uint64_t>();
    sweep.count = in.get<uint64_t>();
    sweep.size = in.get<uint64_t>();
    sweep.done_before = in.get<uint64_t>();
    done = in.get<uint64_t>();
    next_checkpoint = in.get<uint64_t>();
    half = in.get<uint64_t>();
    timed_rounds = in.get<uint64_t>();
    alpha_sum = in.get<double>();
    // The merged α tally is kept by the first block.
    blocks.front().alpha = in.get<AlphaTally>();
    stats_.swaps = in.get<uint64_t>();
    stats_.tree_seconds = in.get<double>();
    in.expect_end();
    // Every count that steers the loop is checked, so that a damaged state can neither
    // loop forever nor index past the chains.
    uint64_t left = 0;
    bool consistent = half <= 1 && is_checkpoint(next_checkpoint) && next_checkpoint <= (1ull << 40) &&
                      is_checkpoint(timed_rounds) && timed_rounds <= (1ull << 40) &&
                      std::isfinite(stats_.b) && stats_.b > 0.0 && std::isfinite(alpha_sum);
    for (const int64_t u : units) consistent &= u >= 0;
    if (consistent && sweep.active) {
      // (first + count could wrap around.)
      consistent = sweep.count > 0 && sweep.first < uint64_t(chain_count) &&
                   sweep.count <= uint64_t(chain_count) - sweep.first &&
                   (!ensemble || (sweep.first == half * ensemble_size && sweep.count == ensemble_size));
      // The chains take every step a state promises them, so the sweep is held to what the
      // loop below gives one: it never crosses a checkpoint, and takes `it` steps per path
      // in EMLT, at most its rounds in a timed MLT render.
      const uint64_t round_steps = std::max<uint64_t>(pixels, uint64_t(chain_count));
      uint64_t most = 0, rounds = 0;
      if (__builtin_mul_overflow(next_checkpoint, pixels, &most)) most = UINT64_MAX;
      most -= std::min(most, sweep.done_before);
      if (ensemble)
        most = std::min(most, ensemble_size * iterations);
      else if (timed && !__builtin_mul_overflow(timed_rounds, round_steps, &rounds))
        most = std::min(most, rounds);
      consistent = consistent && sweep.size <= most;
    }
    for (uint64_t c = 0; consistent && c < uint64_t(chain_count); ++c) {
      const uint64_t chain_left = chains[size_t(c)].sweep_left;
      const bool in_sweep = sweep.active && c >= sweep.first && c < sweep.first + sweep.count;
      consistent = in_sweep ? chain_left <= sweep.size : chain_left == 0;
      left += chain_left;
    }
    // (Under MPI a rank holds only its own chains' steps left, and `done` counts every rank's.)
    if (consistent && sweep.active)
      consistent = left <= sweep.size && done <= sweep.done_before + sweep.size &&
                   done >= sweep.done_before;
    if (!consistent) throw StateError("the saved chains' schedule is inconsistent");
    // A sweep under way is finished before anything else (and cannot be cut short).
    const uint64_t committed = sweep.active ? sweep.done_before + sweep.size : done;
    if (!timed && committed > planned)
      throw StateError("the checkpoint has " + std::to_string(committed / pixels) +
                       " mutations per pixel done or under way, more than this run's budget of " +
                       std::to_string(planned / pixels) +
                       " (a resumed render may extend the budget, not cut it)");
    chain_in.reset();
    chain_section.clear();
  }
  // Which rank moves a chain (every chain belongs to one block of its sweep).
  const auto owns_chain = [&](uint64_t c) {
    const uint64_t j = ensemble && c >= ensemble_size ? c - ensemble_size : c;
    return j >= first_owned_chain && j < end_owned_chain;
  };
  // EMLT under MPI: a rank holds the other ranks' chains only as guide copies (the paths
  // they moved, in PathCodec's guide form), which are no chains to resume from. It saves
  // them as chains without a path, and a resumed run has every rank send its own chains
  // again before the first sweep.
  const bool guide_copies = ensemble && cluster::size() > 1;
  const auto save_chains = [&](StateWriter& out) {
    out.put<double>(stats_.b);
    out.put<double>(stats_.b_standard_error);
    out.put<uint64_t>(stats_.bootstrap_samples);
    out.put<double>(stats_.bootstrap_seconds);
    out.put<uint64_t>(chains.size());
    for (size_t c = 0; c < chains.size(); ++c) {
      const Chain& chain = chains[c];
      if (guide_copies && !owns_chain(c)) {
        codec.save(Path{}, out);
        out.put(DVec3(0.0));
        out.put(0.0);
        out.put(0.0);
      } else {
        codec.save(chain.current, out);
        out.put(chain.contribution);
        out.put(chain.target);
        out.put(chain.carried);
      }
      out.put(chain.rng.save());
      out.put(chain.steps_taken);
      out.put(chain.sweep_left);
    }
    for (const BlockOutput& block : blocks)
      for (const StrategyStats& stats : block.stats) out.put<StrategyStats>(stats);
    std::vector<int64_t> units;
    if (!FixedPointFilm::total_units(films, units))
      throw Error("the MCMC film overflowed: too many mutations' worth of weight in one pixel");
    out.put_vector(units);
    units.clear();
    if (record_moves && !FixedPointFilm::total_units(move_films, units))
      throw Error("the --aniso-map tallies overflowed: too many proposals per pixel");
    out.put_vector(units);
    out.put(sweep.active);
    out.put(sweep.first);
    out.put(sweep.count);
    out.put(sweep.size);
    out.put(sweep.done_before);
    out.put(done);
    out.put(next_checkpoint);
    out.put(half);
    out.put(timed_rounds);
    out.put(alpha_sum);
    AlphaTally alpha;
    for (const BlockOutput& block : blocks) alpha.merge(block.alpha);
    out.put(alpha);
    out.put(stats_.swaps);
    out.put(stats_.tree_seconds);
  };
  const auto save_all = [&](StateWriter& out) { run.save(out, save_chains); };

  // The image after `mutations` steps: the direct part, plus the films' sum and each chain's
  // weight not yet splatted (added to a copy: the chains go on untouched), scaled so the
  // image's mean luminance is b.
  uint64_t live = 0;  // chains with a seed (all, in practice): counted once every rank has them
  // Moved out rather than copied: result.image is set again from compose() at the end.
  Image direct_image = std::move(result.image);
  // Complete on rank 0 (the films and the chains' unsplatted weights summed over ranks).
  // It runs while the chains and films are held, at the render's peak memory: each buffer
  // is released as soon as it is used, and the last call (`last`) takes the direct image
  // instead of copying it.
  const auto compose = [&](uint64_t mutations_done, bool last = false) {
    std::vector<DVec3> total(pixels, DVec3(0.0));
    const auto overflowed = [] {
      return Error(
          "the MCMC film overflowed: more than 4e10 mutations' worth of weight in one "
          "pixel (use fewer mutations per pixel or a larger image)");
    };
    if (cluster::size() == 1) {
      // One process: each pixel straight from the films (the same integer sums, converted
      // the same way), without the whole image of them as integers beside `total`.
      for (const FixedPointFilm& film : films)
        if (film.overflowed()) throw overflowed();
      for (uint64_t p = 0; p < pixels; ++p)
        if (!FixedPointFilm::total(films, p, total[p])) throw overflowed();
    } else {
      std::vector<int64_t> units;
      if (!FixedPointFilm::total_units(films, units)) throw overflowed();
      cluster::sum_to_root(units);
      for (uint64_t p = 0; p < pixels; ++p)
        total[p] = DVec3(double(units[3 * p]), double(units[3 * p + 1]), double(units[3 * p + 2])) /
                   FixedPointFilm::kUnitsPerValue;
    }
    {
      std::vector<double> carried(kCarriedFields * chains.size(), 0.0);
      for (size_t c = 0; c < chains.size(); ++c)
        if (owns_chain(c))
          put_carried(carried, c,
                      chains[c].current.vertices.empty() ? Vec2(0.0f) : chains[c].current.raster(),
                      chains[c].contribution, chains[c].target, chains[c].carried);
      cluster::sum_to_root(carried);
      for (size_t c = 0; c < chains.size(); ++c) {
        const double* f = &carried[kCarriedFields * c];
        splat(total, width, height, scene.camera().filter(), Vec2(float(f[0]), float(f[1])),
              DVec3(f[2], f[3], f[4]), f[5], f[6]);
      }
    }
    const double splatted = double(mutations_done) * double(live) / double(chain_count);
    const double scale = splatted > 0.0 ? double(pixels) * b / splatted : 0.0;
    Image image = last ? std::move(direct_image) : direct_image;
    for (uint64_t p = 0; p < pixels; ++p) image.pixels[p] += Rgb(total[p] * scale);
    return image;
  };
  // Every block's counters on rank 0 (a block's are its owner's; the others hold zeros).
  const auto block_stats = [&] {
    std::vector<uint64_t> counts;
    std::vector<double> sums;
    for (const BlockOutput& block : blocks)
      for (const StrategyStats& st : block.stats) {
        counts.insert(counts.end(), {st.proposed, st.not_applicable, st.failed, st.accepted, st.fallbacks});
        sums.push_back(st.acceptance_sum);
      }
    cluster::sum_to_root(counts);
    cluster::sum_to_root(sums);
    std::vector<std::vector<StrategyStats>> out(blocks.size(), std::vector<StrategyStats>(mix.size()));
    for (size_t b = 0, k = 0; b < blocks.size(); ++b)
      for (size_t i = 0; i < mix.size(); ++i, ++k) {
        StrategyStats& st = out[b][i];
        st.proposed = counts[5 * k], st.not_applicable = counts[5 * k + 1];
        st.failed = counts[5 * k + 2], st.accepted = counts[5 * k + 3];
        st.fallbacks = counts[5 * k + 4], st.acceptance_sum = sums[k];
      }
    return out;
  };
  const auto acceptance_so_far = [&] {
    const auto stats = block_stats();
    std::vector<StrategyAcceptance> out;
    for (size_t i = 0; i < mix.size(); ++i) {
      StrategyStats merged;
      for (const auto& block : stats) merged.merge(block[i]);
      out.push_back({mix.name(i), merged.mean_acceptance()});
    }
    return out;
  };
  const auto take_snapshot = [&](uint64_t mutations_done) {
    const auto begin = std::chrono::steady_clock::now();
    settings.snapshots->snapshot(double(mutations_done) / double(pixels), run.counted_seconds(),
                                 compose(mutations_done), acceptance_so_far());
    run.write_off(std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
  };

  // EMLT's view of the frozen half, rebuilt at every swap.
  EnsembleGuides guides;
  EnsembleParams ensemble_params = options_.ensemble_params;
  if (settings.ensemble_neighbours > 0) ensemble_params.neighbours = settings.ensemble_neighbours;
  if (settings.ensemble_similarity_length > 0.0)
    ensemble_params.similarity_length = settings.ensemble_similarity_length;
  if (!(ensemble_params.similarity_length > 0.0))
    ensemble_params.similarity_length = double(scene.bounds_radius()) / std::sqrt(3.0);
  ensemble_params.plane_fallback = settings.ensemble_plane_fallback;
  if (settings.ensemble_aniso_weighted) ensemble_params.aniso_printed_covariance = false;
  if (settings.ensemble_aniso_scale > 0.0)
    ensemble_params.aniso_covariance_scale = settings.ensemble_aniso_scale;
  ensemble_params.aniso_smallest_scale = settings.ensemble_aniso_smallest_scale;
  if (settings.ensemble_nearby_guides) ensemble_params.selection = GuideSelection::Nearby;
  if (settings.ensemble_alpha_from_ensemble) ensemble_params.alpha_source = AlphaSource::Ensemble;
  if (settings.ensemble_alpha > 0.0) {
    ensemble_params.adaptive_alpha = false;
    ensemble_params.alpha_fixed = settings.ensemble_alpha;
  }
  std::vector<const Path*> frozen(ensemble_size);
  bool guides_ready = false;
  if (ensemble) ctx.ensemble = &guides;
  const StepRules rules{options_.ignore_selection_probability, settings.mlt_expected_values,
                        options_.drop_rejected_steps};
  tbb::task_arena arena(threads);
  // Y's tree and α from the frozen half (the other one than the sweep's), which nothing
  // changes during the sweep: rebuilding it on resume gives the same guides. Built on the
  // render's threads (the arena), not every core of the machine.
  const auto build_guides = [&] {
    const auto tree_start = std::chrono::steady_clock::now();
    const uint64_t other = (1 - half) * ensemble_size;
    for (uint64_t i = 0; i < ensemble_size; ++i) {
      const Chain& y = chains[size_t(other + i)];
      frozen[i] = y.target > 0.0 ? &y.current : nullptr;
    }
    arena.execute([&] { guides.build(frozen, width, height, settings.seed, ensemble_params); });
    stats_.tree_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - tree_start).count();
    guides_ready = true;
  };

  progress.start(options_.name.c_str(), timed ? 0 : planned, settings.time_limit_s);
  progress.advance(done);
  // Under MPI, rank 0's clock decides the time budget for every rank (a broadcast).
  // (Without a time budget every rank's value is already the same: nothing to send.)
  const auto root_decides = [&](uint64_t& value) {
    if (cluster::size() == 1 || !timed) return;
    StateWriter out;
    out.put(value);
    std::string data = out.take();
    cluster::broadcast(data);
    value = StateReader(data).get<uint64_t>();
  };
  // EMLT under MPI: after a half-sweep, every rank needs the moved paths of the others, as
  // they are the frozen half that guides the next one.
  SweepProfile profile;
  // Only the paths that moved are sent: the others are as every rank already has them.
  // Each block packs its chains' as soon as a chain has taken its steps, while the path is
  // in cache (packing them after the sweep fetched every path from memory again). The
  // writers are kept across swaps, with their memory.
  struct PackedPaths {
    std::vector<uint32_t> ids;
    StateWriter records;  // for each of ids: the chain's target, its path in guide form
  };
  std::vector<PackedPaths> packed(guide_copies ? blocks.size() : 0);
  const auto pack_moved = [&](uint64_t c, PackedPaths& out) {
    Chain& chain = chains[c];
    chain.moved = false;
    out.ids.push_back(uint32_t(c));
    out.records.put(chain.target);
    PathCodec::pack_guide(chain.current, out.records);
  };
  StateWriter exchange;
  std::vector<uint32_t> all_ids;
  // What this rank sends (into `exchange`): the blocks' packed paths, the chains' indices
  // first, so that the receiver can ask for the paths it will overwrite ahead of time (they
  // lie scattered in memory). The blocks keep theirs until they are sent: a sweep cut
  // short goes on packing. Returns every rank's length in bytes as far as this rank knows
  // it (its own; zeros for the others): their maxima over the ranks are every rank's.
  const auto prepare_moved_paths = [&] {
    const double t0 = profile.enabled ? SweepProfile::now() : 0.0;
    all_ids.clear();
    for (const PackedPaths& block : packed)
      all_ids.insert(all_ids.end(), block.ids.begin(), block.ids.end());
    StateWriter& mine = exchange;
    mine.clear();
    mine.put_vector(all_ids);
    mine.put<uint64_t>(packed.size());
    for (const PackedPaths& block : packed) mine.put_block(block.records.data());
    std::vector<uint64_t> lengths(size_t(cluster::size()), 0);
    lengths[size_t(cluster::rank())] = mine.data().size();
    if (profile.enabled) profile.pack += SweepProfile::now() - t0;
    return lengths;
  };
  // Sends what prepare_moved_paths prepared, every rank's length known, and takes in the
  // other ranks' paths.
  const auto share_moved_paths = [&](std::span<const uint64_t> lengths) {
    const double t1 = profile.enabled ? SweepProfile::now() : 0.0;
    for (PackedPaths& block : packed) {
      block.ids.clear();
      block.records.clear();
    }
    profile.bytes_sent += exchange.data().size();
    const std::vector<std::string_view> parts = cluster::gather_everywhere(exchange.data(), lengths);
    const double t2 = profile.enabled ? SweepProfile::now() : 0.0;
    constexpr size_t kAhead = 4;
    for (size_t r = 0; r < parts.size(); ++r) {
      if (int(r) == cluster::rank()) continue;
      StateReader in(parts[r]);
      const std::vector<uint32_t> ids = in.get_vector_up_to<uint32_t>(chains.size());
      const uint64_t block_count = in.get<uint64_t>();
      size_t k = 0;
      for (uint64_t b = 0; b < block_count; ++b) {
        StateReader records(in.get_block());
        for (; records.remaining() > 0; ++k) {
          if (k + kAhead < ids.size()) {
            const Chain& ahead = chains.at(ids[k + kAhead]);
            __builtin_prefetch(&ahead);
            prefetch_path(ahead.current);
          }
          Chain& chain = chains.at(ids.at(k));
          chain.target = records.get<double>();
          PathCodec::unpack_guide(records, chain.current);
        }
      }
      if (k != ids.size()) throw StateError("the moved paths of a rank are damaged");
    }
    if (profile.enabled) profile.gather += t2 - t1, profile.unpack += SweepProfile::now() - t2;
  };
  // Sweeps: for MLT, every chain takes its share of the steps up to the next checkpoint (a
  // power of two in mutations per pixel) in one visit, so that its path stays in cache
  // (one round of a mutation per pixel at a time ran 10 % slower with 16384 chains); a
  // timed render starts with one round and doubles the sweep while sweeps are short, since
  // the time budget is checked between sweeps. For EMLT, half-sweeps of `it` steps for
  // each path of X. No sweep crosses a checkpoint, so snapshots fall on them exactly. A
  // pause (a checkpoint falling due, a stop) cuts a sweep short with every chain's steps
  // left recorded; the sweep then goes on from there, in this process or a resumed one.
  const uint64_t round_size = std::max<uint64_t>(pixels, uint64_t(chain_count));
  // A resumed rank holds only its own chains (save_chains): every rank sends them, and the
  // others' guide copies are whole again.
  if (resumed && guide_copies) {
    for (uint64_t c = 0; c < chains.size(); ++c)
      if (owns_chain(c)) pack_moved(c, packed[0]);
    std::vector<uint64_t> lengths = prepare_moved_paths();
    cluster::max_everywhere(lengths);
    share_moved_paths(lengths);
  }
  for (const Chain& chain : chains) live += chain.target > 0.0;
  bool stopped = false;
  while (true) {
    if (!sweep.active) {
      uint64_t time_up = timed && run.counted_seconds() >= settings.time_limit_s;
      root_decides(time_up);
      if (done >= planned || time_up) break;
      sweep.first = 0;
      sweep.count = uint64_t(chain_count);
      sweep.size = timed ? timed_rounds * round_size : planned - done;
      if (ensemble) {
        sweep.first = half * ensemble_size;
        sweep.count = ensemble_size;
        sweep.size = ensemble_size * iterations;
        const double guides_start = profile.enabled ? SweepProfile::now() : 0.0;
        build_guides();
        if (profile.enabled) profile.guides += SweepProfile::now() - guides_start;
        alpha_sum += guides.alpha();
      }
      sweep.size = std::min(sweep.size, planned - done);
      if (done < next_checkpoint * pixels)
        sweep.size = std::min(sweep.size, next_checkpoint * pixels - done);
      for (uint64_t j = 0; j < sweep.count; ++j) {
        Chain& chain = chains[size_t(sweep.first + j)];
        chain.sweep_left = !(chain.target > 0.0) || !owns_chain(sweep.first + j)
                               ? 0
                               : sweep.size / sweep.count + (j < sweep.size % sweep.count ? 1 : 0);
      }
      sweep.done_before = done;
      sweep.active = 1;
    } else if (ensemble && !guides_ready) {
      build_guides();
    }
    const double sweep_start = elapsed();
    const uint64_t first = sweep.first, count = sweep.count;
    const int block_count = int(std::min<uint64_t>(count, blocks.size()));
    const double steps_start = profile.enabled ? SweepProfile::now() : 0.0,
                 steps_cpu_start = profile.enabled ? SweepProfile::thread_cpu() : 0.0;
    arena.execute([&] {
      tbb::parallel_for(0, block_count, [&](int block) {
        if (!owns_block(uint64_t(block))) return;
        const uint64_t begin = count * uint64_t(block) / uint64_t(block_count);
        const uint64_t end = count * uint64_t(block + 1) / uint64_t(block_count);
        // Progress once per block: a shared counter per chain would bounce between cores
        // (EMLT chains take one step at a time).
        uint64_t block_steps = 0;
        const size_t slot =
            size_t(std::max(tbb::this_task_arena::current_thread_index(), 0)) % films.size();
        const FilmSlot film{films[slot], record_moves ? &move_films[slot] : nullptr, shared_films,
                            scene.camera().filter()};
        for (uint64_t j = begin; j < end; ++j) {
          Chain& chain = chains[size_t(first + j)];
          if (j + 1 < end) prefetch_path(chains[size_t(first + j + 1)].current);
          if (chain.sweep_left == 0) continue;
          if (interruption::requested()) break;
          const uint64_t steps = run_chain(chain, first + j, mix, ctx, rules, blocks[size_t(block)],
                                           film, width, height);
          if (guide_copies && chain.moved) pack_moved(first + j, packed[size_t(block)]);
          interruption::poll(steps);
          block_steps += steps;
        }
        progress.advance(block_steps);
      });
    });
    // The steps left of every rank's chains: a pause on any rank pauses all of them, at the
    // same point of the loop (interruption.h).
    if (profile.enabled) {
      profile.steps += SweepProfile::now() - steps_start;
      profile.steps_cpu += SweepProfile::thread_cpu() - steps_cpu_start;
    }
    std::vector<uint64_t> left = {0};
    for (uint64_t j = 0; j < count; ++j) left[0] += chains[size_t(first + j)].sweep_left;
    // EMLT under MPI: the lengths of the moved paths to exchange are agreed on with the rest.
    std::vector<uint64_t> lengths = guide_copies ? prepare_moved_paths() : std::vector<uint64_t>();
    const double agreement_start = profile.enabled ? SweepProfile::now() : 0.0;
    const interruption::Decision decision = interruption::agree(left[0] > 0, lengths);
    // (A complete sweep has no steps left on any rank: no sum to take.)
    if (decision.incomplete) cluster::sum_everywhere(left);
    if (profile.enabled) profile.agreement += SweepProfile::now() - agreement_start;
    done = sweep.done_before + sweep.size - left[0];
    if (!decision.incomplete) {
      sweep.active = 0;
      uint64_t rounds = timed_rounds;
      if (timed && !ensemble &&
          elapsed() - sweep_start < std::min(0.05, settings.time_limit_s / 50.0))
        rounds *= 2;
      root_decides(rounds);
      timed_rounds = rounds;
      if (ensemble) {
        if (guide_copies) share_moved_paths(lengths);
        half = 1 - half;
        ++stats_.swaps;
        guides_ready = false;
      }
      for (; done >= next_checkpoint * pixels; next_checkpoint *= 2)
        if (settings.snapshots && done == next_checkpoint * pixels) take_snapshot(done);
    }
    if (decision.pause()) {
      RenderControl::pause(control, save_all);
      if (decision.stop && (decision.incomplete || done < planned)) {
        stopped = true;
        break;
      }
    }
  }
  profile.print();
  if (settings.snapshots && !(done % pixels == 0 && is_checkpoint(done / pixels)))
    take_snapshot(done);
  if (!stopped) RenderControl::finish(control, save_all);
  progress.finish();

  result.image = compose(done, true);
  result.interrupted = stopped;
  if (record_moves) {
    std::vector<int64_t> units;
    if (!FixedPointFilm::total_units(move_films, units))
      throw Error("the --aniso-map tallies overflowed: too many proposals per pixel");
    cluster::sum_to_root(units);
    if (cluster::is_root()) {
      std::vector<FixedPointFilm> merged(1, FixedPointFilm(pixels, 256.0));
      FixedPointFilm::load_units(merged, units);
      write_move_map(settings.aniso_map_path, merged, width, height);
    }
  }
  {
    // α's tally over the blocks and ranks: counts and sum add up; the extremes of positive
    // doubles order as their bit patterns, so a maximum over ranks gives both.
    AlphaTally alpha;
    for (const BlockOutput& block : blocks) alpha.merge(block.alpha);
    if (cluster::size() > 1) {
      std::vector<uint64_t> counts(alpha.counts.begin(), alpha.counts.end());
      std::vector<double> sum{alpha.sum};
      cluster::sum_to_root(counts);
      cluster::sum_to_root(sum);
      const auto bits = [](double v) { return std::bit_cast<uint64_t>(std::max(v, 0.0)); };
      std::vector<uint64_t> extremes{~bits(std::isfinite(alpha.min) ? alpha.min : 1e300),
                                     bits(std::isfinite(alpha.max) ? alpha.max : 0.0)};
      cluster::max_everywhere(extremes);
      std::copy(counts.begin(), counts.end(), alpha.counts.begin());
      alpha.sum = sum[0];
      alpha.min = std::bit_cast<double>(~extremes[0]);
      alpha.max = std::bit_cast<double>(extremes[1]);
      if (alpha.total() == 0) alpha = AlphaTally{};
    }
    stats_.alpha = alpha;
  }
  const auto merged_blocks = block_stats();
  for (const auto& block : merged_blocks)
    for (size_t i = 0; i < mix.size(); ++i) stats_.strategies[i].merge(block[i]);
  stats_.chains = uint64_t(chain_count);
  stats_.mutations = done;
  stats_.seconds = run.counted_seconds();
  if (ensemble) {
    stats_.ensemble_size = ensemble_size;
    stats_.ensemble_neighbours = uint64_t(ensemble_params.neighbours);
    stats_.ensemble_iterations = iterations;
    stats_.mean_alpha = stats_.swaps ? alpha_sum / double(stats_.swaps) : 0.0;
    if (stats_.alpha.total() > 0) stats_.mean_alpha = stats_.alpha.mean();
  }
  result.seconds = stats_.seconds;
  result.samples = done;
  result.samples_per_pixel = int(std::llround(double(done) / double(pixels)));
  result.per_pixel = double(done) / double(pixels);
  return result;
}

}  // namespace emlt
