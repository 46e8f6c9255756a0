#include "emlt/mcmc/pss_integrator.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/mcmc/bootstrap.h"
#include "emlt/mcmc/fixed_point_film.h"
#include "emlt/render/bdpt.h"
#include "emlt/render/direct_integrator.h"
#include "emlt/render/interruption.h"
#include "emlt/render/pixel_renderer.h"
#include "emlt/render/snapshot.h"

namespace emlt {

namespace {

constexpr uint64_t kBootstrapStream = 0xb5500ull << 40;
constexpr uint64_t kChainStream = 0xc5500ull << 40;
constexpr uint64_t kSeedStream = 0x55eedull << 40;
constexpr int kBlocks = 64;
constexpr int kMaxFilms = 16;
constexpr size_t kLarge = 0, kSmall = 1;  // the step kinds' statistics

struct Chain {
  PrimarySampleVector u;
  PssSample current;
  double carried = 0.0;  // (1 - a) summed over the steps since x became current
  Rng rng;
  int length = 0;      // MMLT: the chain's path length
  double b = 0.0;      // its normalisation (b, or b_k)
  double scale = 1.0;  // MMLT: (b_k / b) (chains / chains of length k); 1 for PSSMLT
};

// Adds weight * F / (f* + p_L b) of every contribution, at its raster position.
void splat(FixedPointFilm& film, bool shared, const PixelFilter& filter, int width, int height,
           const PssSample& sample, double weight, double denominator) {
  if (!(weight > 0.0) || !(denominator > 0.0)) return;
  const double w = weight / denominator;
  for (const PssSplat& s : sample.splats) {
    const DVec3 value = DVec3(s.value) * w;
    if (filter.is_box()) {
      const int x = std::clamp(int(s.raster.x), 0, width - 1),
                y = std::clamp(int(s.raster.y), 0, height - 1);
      film.add(size_t(y) * size_t(width) + size_t(x), value, shared);
    } else {
      filter.splat(s.raster,
                   [&](uint32_t pixel, float fw) { film.add(pixel, value * double(fw), shared); });
    }
  }
}

// The bootstrap's evaluation of sample i (also the chains' seeds, rebuilt the same way).
void bootstrap_sample(const PrimarySampleTracer& tracer, uint64_t seed, uint64_t i, int length,
                      float sigma, PrimarySampleVector& u, PssSample& out) {
  u = PrimarySampleVector(sigma);
  Rng rng = Rng::for_item(derive_stream_seed(seed, kBootstrapStream), i);
  u.begin(true);
  tracer.evaluate(u, rng, length, out);
  u.accept();
}

}  // namespace

RenderResult PssMltIntegrator::render(const Scene& scene, const RenderSettings& settings,
                                      ProgressReporter& progress) const {
  if (cluster::size() > 1)
    throw Error(name() + " does not run under MPI yet: run it as one process");
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  const bool multiplexed = options_.multiplexed;
  const double p_large = std::clamp(settings.large_step_probability, 0.0, 1.0);
  const float sigma = float(settings.pss_sigma);
  stats_ = MltStatistics{};

  const int min_edges = settings.direct_separate ? 3 : 1;
  const int max_edges = settings.max_depth < 0 ? BidirectionalPathTracer::kUnlimitedDepth
                                               : std::min(settings.max_depth, kMaxPathVertices - 1);
  RenderResult result;
  result.image = Image(width, height);
  double snapshot_seconds = 0.0;
  if (settings.direct_separate) {
    PixelRenderState direct_state;
    const RenderResult direct_result = render_direct_pass(scene, settings, direct_state, [] {});
    result.image = direct_result.image;
    stats_.direct_spp = direct_result.samples_per_pixel;
    stats_.direct_seconds = direct_result.seconds;
    if (direct_result.interrupted) {
      result.interrupted = true;
      result.stopped_in = "the direct-light pass";
      result.seconds = stats_.seconds = elapsed();
      return result;
    }
  }
  if (min_edges > max_edges) {
    result.seconds = elapsed();
    return result;
  }
  const PssTracer kind = multiplexed         ? PssTracer::Multiplexed
                         : settings.pss_bdpt ? PssTracer::Bdpt
                                             : PssTracer::PathTracer;
  const PrimarySampleTracer tracer(scene, settings, kind, min_edges, max_edges,
                                   options_.ignore_technique_selection);
  const int threads =
      settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);

  // The chains' seeds: N independent samples (a large step each); MMLT gives sample i the
  // length min + i mod K, so every length gets N / K of them.
  const double bootstrap_start = elapsed();
  const int lengths = multiplexed ? max_edges - min_edges + 1 : 1;
  const uint64_t samples = uint64_t(std::max(settings.bootstrap_samples, lengths));
  const auto length_of = [&](uint64_t i) { return multiplexed ? min_edges + int(i % lengths) : 0; };
  std::vector<double> weights(samples, 0.0);
  arena.execute([&] {
    tbb::parallel_for(0, kBlocks, [&](int block) {
      PrimarySampleVector u(sigma);
      PssSample sample;
      for (uint64_t i = samples * uint64_t(block) / kBlocks;
           i < samples * uint64_t(block + 1) / kBlocks; ++i) {
        bootstrap_sample(tracer, settings.seed, i, length_of(i), sigma, u, sample);
        weights[i] = std::isfinite(sample.target) ? sample.target : 0.0;
      }
    });
  });
  // The pool of each length, in sample order, for the chains' seeds.
  std::vector<std::vector<uint64_t>> pool(static_cast<size_t>(lengths));
  std::vector<std::vector<double>> cumulative(static_cast<size_t>(lengths));
  for (uint64_t i = 0; i < samples; ++i) {
    const size_t k = multiplexed ? size_t(i % uint64_t(lengths)) : 0;
    if (weights[i] > 0.0) {
      pool[k].push_back(i);
      cumulative[k].push_back((cumulative[k].empty() ? 0.0 : cumulative[k].back()) + weights[i]);
    }
  }
  // b (b_k) from MLT's path-space bootstrap (bootstrap.h): the same expectation, the mean
  // luminance of the image (of its paths of k segments), as f* (f*_k) over the unit cube,
  // but every BDPT sample adds to every length at once, with MIS: b_k's error is the
  // error of the length's whole share of the image, and 100 000 MMLT samples spread over
  // 28 lengths measured 2.5 % on b against 0.3 % this way (Cornell box).
  BootstrapParams bp;
  bp.seed = settings.seed;
  bp.samples = settings.bootstrap_samples;
  bp.min_edges = min_edges;
  bp.max_edges = max_edges;
  bp.rr_depth = settings.rr_depth;
  bp.mis = settings.mis;
  bp.threads = threads;
  const Bootstrap path_bootstrap = run_bootstrap(scene, bp);
  if (path_bootstrap.interrupted) {
    result.interrupted = true;
    result.stopped_in = "the bootstrap";
    result.seconds = stats_.seconds = elapsed();
    return result;
  }
  std::vector<double> b_length(static_cast<size_t>(lengths), 0.0);
  for (const BootstrapCandidate& c : path_bootstrap.candidates) {
    const int k = multiplexed ? int(c.s) + int(c.t) - 1 - min_edges : 0;
    if (k >= 0 && k < lengths) b_length[size_t(k)] += double(c.weight);
  }
  double b = 0.0;
  for (size_t k = 0; k < size_t(lengths); ++k) {
    b_length[k] /= double(path_bootstrap.samples);
    // A length without a seed cannot have a chain (nor, in practice, light).
    if (pool[k].empty()) b_length[k] = 0.0;
    b += b_length[k];
  }
  stats_.b = b;
  stats_.b_standard_error = path_bootstrap.standard_error;
  stats_.bootstrap_samples = path_bootstrap.samples;
  if (!(b > 0.0)) {
    stats_.bootstrap_seconds = elapsed() - bootstrap_start;
    std::fprintf(
        stderr,
        "emlt: warning: no bootstrap sample carries light; the MCMC part of the image is black\n");
    result.seconds = stats_.seconds = elapsed();
    return result;
  }

  // Chains; for MMLT shared among the lengths in proportion to b_k, at least one for every
  // length the bootstrap saw light in (largest remainders, in length order).
  const bool timed = settings.time_limit_s > 0.0;
  const uint64_t budget =
      uint64_t(std::llround(std::max(settings.mutations_per_pixel, 0.0) * double(pixels)));
  int chain_count = settings.chains > 0
                        ? settings.chains
                        : MltIntegrator::default_chain_count(timed ? pixels * 16 : budget);
  std::vector<int> chains_of_length(static_cast<size_t>(lengths), 0);
  if (multiplexed) {
    int lit = 0;
    for (size_t k = 0; k < size_t(lengths); ++k) lit += b_length[k] > 0.0;
    chain_count = std::max(chain_count, lit);
    int given = 0;
    std::vector<std::pair<double, size_t>> remainders;
    for (size_t k = 0; k < size_t(lengths); ++k) {
      if (!(b_length[k] > 0.0)) continue;
      const double share = double(chain_count - lit) * b_length[k] / b;
      chains_of_length[k] = 1 + int(std::floor(share));
      given += chains_of_length[k];
      remainders.push_back({share - std::floor(share), k});
    }
    std::stable_sort(remainders.begin(), remainders.end(),
                     [](const auto& x, const auto& y) { return x.first > y.first; });
    for (size_t i = 0; given < chain_count && i < remainders.size(); ++i, ++given)
      ++chains_of_length[remainders[i].second];
  } else {
    chains_of_length[0] = chain_count;
  }
  std::vector<Chain> chains(static_cast<size_t>(chain_count));
  {
    size_t c = 0;
    for (size_t k = 0; k < size_t(lengths); ++k)
      for (int j = 0; j < chains_of_length[k]; ++j, ++c) {
        Chain& chain = chains[c];
        chain.length = multiplexed ? min_edges + int(k) : 0;
        chain.b = b_length[k];
        chain.scale =
            multiplexed ? (b_length[k] / b) * double(chain_count) / chains_of_length[k] : 1.0;
        chain.rng = Rng::for_item(derive_stream_seed(settings.seed, kChainStream), c);
      }
  }
  arena.execute([&] {
    tbb::parallel_for(0, chain_count, [&](int c) {
      Chain& chain = chains[size_t(c)];
      const size_t k = multiplexed ? size_t(chain.length - min_edges) : 0;
      Rng seed_rng = Rng::for_item(derive_stream_seed(settings.seed, kSeedStream), uint64_t(c));
      const double target = seed_rng.uniform_double() * cumulative[k].back();
      const size_t index =
          std::min(size_t(std::upper_bound(cumulative[k].begin(), cumulative[k].end(), target) -
                          cumulative[k].begin()),
                   pool[k].size() - 1);
      bootstrap_sample(tracer, settings.seed, pool[k][index], chain.length, sigma, chain.u,
                       chain.current);
    });
  });
  stats_.bootstrap_seconds = elapsed() - bootstrap_start;
  stats_.chains = uint64_t(chain_count);

  // Statistics: the step kinds, then (MMLT) the lengths; counted per block of chains.
  stats_.strategy_names = {"large", "small"};
  if (multiplexed)
    for (int k = min_edges; k <= max_edges; ++k)
      stats_.strategy_names.push_back("length " + std::to_string(k));
  const size_t stat_count = stats_.strategy_names.size();
  struct alignas(64) BlockStats {
    std::vector<StrategyStats> stats;
  };
  const int block_count = std::min(chain_count, kBlocks);
  std::vector<BlockStats> blocks(static_cast<size_t>(block_count));
  for (BlockStats& block : blocks) block.stats.assign(stat_count, StrategyStats{});
  std::vector<FixedPointFilm> films(size_t(std::min(threads, kMaxFilms)), FixedPointFilm(pixels));
  const bool shared_films = size_t(threads) > films.size();
  const PixelFilter& filter = camera.filter();

  // One step of a chain (Kelemen's estimator; see pss_integrator.h).
  const auto step = [&](Chain& chain, PssSample& proposal, FixedPointFilm& film,
                        std::vector<StrategyStats>& stats) {
    const bool large = chain.rng.uniform() < p_large;
    chain.u.begin(large);
    tracer.evaluate(chain.u, chain.rng, chain.length, proposal);
    double a = 0.0;
    if (proposal.target > 0.0 && std::isfinite(proposal.target))
      a = std::min(1.0, proposal.target / chain.current.target);
    else
      proposal.target = 0.0;
    StrategyStats& kind_stats = stats[large ? kLarge : kSmall];
    ++kind_stats.proposed;
    kind_stats.acceptance_sum += a;
    if (!(proposal.target > 0.0)) ++kind_stats.failed;
    StrategyStats* length_stats =
        multiplexed ? &stats[2 + size_t(chain.length - min_edges)] : nullptr;
    if (length_stats) {
      ++length_stats->proposed;
      length_stats->acceptance_sum += a;
    }
    const double pb = p_large * chain.b;
    const double proposal_weight =
        (a + (large && !options_.drop_large_step_weight ? 1.0 : 0.0)) * chain.scale;
    splat(film, shared_films, filter, width, height, proposal, proposal_weight,
          proposal.target + pb);
    chain.carried += 1.0 - a;
    if (chain.rng.uniform() < a) {
      splat(film, shared_films, filter, width, height, chain.current, chain.carried * chain.scale,
            chain.current.target + pb);
      std::swap(chain.current, proposal);
      chain.carried = 0.0;
      chain.u.accept();
      ++kind_stats.accepted;
      if (length_stats) ++length_stats->accepted;
    } else {
      chain.u.reject(options_.keep_coordinate_on_reject);
    }
  };

  // The image after `done` steps: the films plus every chain's weight not yet splatted
  // (added to a copy), scaled by pixels b / steps.
  const Image direct_image = result.image;
  const auto compose = [&](uint64_t done) {
    std::vector<FixedPointFilm> total(1, FixedPointFilm(pixels));
    std::vector<int64_t> units;
    if (!FixedPointFilm::total_units(films, units))
      throw Error("the MCMC film overflowed: too many mutations' worth of weight in one pixel");
    FixedPointFilm::load_units(total, units);
    for (const Chain& chain : chains)
      splat(total[0], false, filter, width, height, chain.current, chain.carried * chain.scale,
            chain.current.target + p_large * chain.b);
    if (!FixedPointFilm::total_units(total, units))
      throw Error("the MCMC film overflowed: too many mutations' worth of weight in one pixel");
    const double scale = done > 0 ? double(pixels) * b / double(done) : 0.0;
    Image image = direct_image;
    for (uint64_t p = 0; p < pixels; ++p)
      image.pixels[p] +=
          Rgb(DVec3(double(units[3 * p]), double(units[3 * p + 1]), double(units[3 * p + 2])) *
              (scale / FixedPointFilm::kUnitsPerValue));
    return image;
  };
  const auto acceptance_so_far = [&] {
    std::vector<StrategyAcceptance> out;
    for (size_t i = 0; i < stat_count; ++i) {
      StrategyStats merged;
      for (const BlockStats& block : blocks) merged.merge(block.stats[i]);
      out.push_back({stats_.strategy_names[i], merged.mean_acceptance()});
    }
    return out;
  };

  // Sweeps: every chain takes the same number of steps, so that MMLT's per-length scale is
  // exact. A budget of mutations is rounded up to whole steps per chain and split at
  // powers of two in mutations per pixel (the log's snapshots); a time budget runs sweeps
  // of `rounds` steps per chain, doubled while a sweep takes under 50 ms.
  const uint64_t planned_steps =
      timed ? (settings.mutations_per_pixel > 0
                   ? (budget + uint64_t(chain_count) - 1) / uint64_t(chain_count)
                   : UINT64_MAX)
            : (budget + uint64_t(chain_count) - 1) / uint64_t(chain_count);
  progress.start(name().c_str(), timed ? 0 : planned_steps * uint64_t(chain_count),
                 settings.time_limit_s);
  uint64_t steps_done = 0, rounds = 1, next_snapshot = 1;
  uint64_t logged = UINT64_MAX;  // the steps of the log's last row
  bool stopped = false;
  std::vector<uint64_t> chain_steps(static_cast<size_t>(chain_count), 0);
  while (steps_done < planned_steps) {
    // (At least one sweep: a budget spent by the bootstrap still gives the chains a round.)
    if (timed && steps_done > 0 && elapsed() - snapshot_seconds >= settings.time_limit_s) break;
    uint64_t sweep = timed ? rounds : planned_steps - steps_done;
    sweep = std::min(sweep, planned_steps - steps_done);
    // Up to the next power of two in mutations per pixel.
    const uint64_t snapshot_steps =
        (next_snapshot * pixels + uint64_t(chain_count) - 1) / uint64_t(chain_count);
    if (snapshot_steps > steps_done) sweep = std::min(sweep, snapshot_steps - steps_done);
    const double sweep_start = elapsed();
    arena.execute([&] {
      tbb::parallel_for(0, block_count, [&](int block) {
        const size_t slot =
            size_t(std::max(tbb::this_task_arena::current_thread_index(), 0)) % films.size();
        PssSample proposal;
        uint64_t block_steps = 0;
        for (int c = chain_count * block / block_count; c < chain_count * (block + 1) / block_count;
             ++c) {
          Chain& chain = chains[size_t(c)];
          uint64_t& taken = chain_steps[size_t(c)];
          const uint64_t before = taken;
          for (; taken < steps_done + sweep; ++taken) {
            if ((taken & 255) == 255 && interruption::requested()) break;
            step(chain, proposal, films[slot], blocks[size_t(block)].stats);
          }
          block_steps += taken - before;
          if (interruption::poll(taken - before)) break;
        }
        progress.advance(block_steps);
      });
    });
    if (interruption::stop_requested()) {
      stopped = true;
      break;
    }
    steps_done += sweep;
    if (timed && elapsed() - sweep_start < std::min(0.05, settings.time_limit_s / 50.0))
      rounds *= 2;
    for (; steps_done * uint64_t(chain_count) >= next_snapshot * pixels; next_snapshot *= 2)
      if (settings.snapshots && steps_done * uint64_t(chain_count) != logged) {
        const auto begin = std::chrono::steady_clock::now();
        const uint64_t done = steps_done * uint64_t(chain_count);
        logged = done;
        settings.snapshots->snapshot(double(done) / double(pixels), elapsed() - snapshot_seconds,
                                     compose(done), acceptance_so_far());
        snapshot_seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
      }
  }
  progress.finish();
  // A stop mid-sweep leaves chains with different step counts: the image then counts the
  // steps actually taken (exact for PSSMLT; MMLT's per-length scale assumes equal counts).
  const uint64_t done = std::accumulate(chain_steps.begin(), chain_steps.end(), uint64_t(0));
  result.image = compose(done);
  // The log ends on the final image unless its last row already is that image.
  if (settings.snapshots && done != logged)
    settings.snapshots->snapshot(double(done) / double(pixels), elapsed() - snapshot_seconds,
                                 result.image, acceptance_so_far());
  result.interrupted = stopped;
  if (stopped) result.stopped_in = "the chains";
  stats_.strategies.assign(stat_count, StrategyStats{});
  for (const BlockStats& block : blocks)
    for (size_t i = 0; i < stat_count; ++i) stats_.strategies[i].merge(block.stats[i]);
  stats_.mutations = done;
  stats_.seconds = elapsed() - snapshot_seconds;
  result.seconds = stats_.seconds;
  result.samples = done;
  result.samples_per_pixel = int(std::llround(double(done) / double(pixels)));
  result.per_pixel = double(done) / double(pixels);
  return result;
}

}  // namespace emlt
