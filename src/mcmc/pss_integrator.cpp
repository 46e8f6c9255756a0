#include "emlt/mcmc/pss_integrator.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/mcmc/bootstrap.h"
#include "emlt/mcmc/fixed_point_film.h"
#include "emlt/mcmc/mcmc_run.h"
#include "emlt/render/bdpt.h"
#include "emlt/render/interruption.h"
#include "emlt/render/pixel_renderer.h"
#include "emlt/render/render_control.h"
#include "emlt/render/snapshot.h"

namespace emlt {

namespace {

constexpr uint64_t kBootstrapStream = 0xb5500ull << 40;
constexpr uint64_t kChainStream = 0xc5500ull << 40;
constexpr uint64_t kSeedStream = 0x55eedull << 40;
constexpr int kBlocks = 64;
constexpr int kMaxFilms = 16;
constexpr size_t kLarge = 0, kSmall = 1;  // the step kinds' statistics
// The phase a checkpoint falls in.
// More splats than any evaluation makes (BDPT's: one per strategy of a path up to
// kMaxPathVertices vertices); a checkpoint's bound.
constexpr uint64_t kMaxSplats = uint64_t(1) << 16;

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
  const Camera& camera = scene.camera();
  const int width = camera.width(), height = camera.height();
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  // The clock (with the runs before a resume), the checkpoint state and the direct pass.
  McmcRun run(settings, width, height);
  const auto elapsed = [&run] { return run.elapsed(); };
  const bool multiplexed = options_.multiplexed;
  const double p_large = std::clamp(settings.large_step_probability, 0.0, 1.0);
  const float sigma = float(settings.pss_sigma);
  stats_ = MltStatistics{};

  const int min_edges = settings.direct_separate ? 3 : settings.shortest_path();
  const int max_edges = settings.max_depth < 0 ? BidirectionalPathTracer::kUnlimitedDepth
                                               : std::min(settings.max_depth, kMaxPathVertices - 1);

  // Checkpoints (render_control.h, mcmc_run.h), as MLT's.
  RenderControl* control = run.control();
  std::string& chain_section = run.chain_section();

  RenderResult result;
  result.image = Image(width, height);
  if (!run.direct_pass(scene, result, stats_)) return result;
  if (min_edges > max_edges) {
    run.finish_before_chains();
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
  const bool timed = settings.time_limit_s > 0.0;
  const uint64_t budget =
      uint64_t(std::llround(std::max(settings.mutations_per_pixel, 0.0) * double(pixels)));
  const int lengths = multiplexed ? max_edges - min_edges + 1 : 1;

  // What the bootstrap decides: b_k for every length (b for PSSMLT) and how many chains
  // each length has. A resumed render takes them from its checkpoint, with the chain count
  // (the default depends on the budget, which a resumed run may extend).
  int chain_count = 0;
  std::vector<double> b_length(static_cast<size_t>(lengths), 0.0);
  std::vector<int32_t> chains_of_length(static_cast<size_t>(lengths), 0);
  std::optional<StateReader> chain_in;
  // Fresh: the pool of each length's bootstrap samples (in sample order) with their
  // cumulative f*, for the chains' seeds.
  std::vector<std::vector<uint64_t>> pool(static_cast<size_t>(lengths));
  std::vector<std::vector<double>> cumulative(static_cast<size_t>(lengths));
  const double bootstrap_start = elapsed();
  if (!chain_section.empty()) {
    chain_in.emplace(chain_section);
    StateReader& in = *chain_in;
    stats_.b_standard_error = in.get<double>();
    stats_.bootstrap_samples = in.get<uint64_t>();
    stats_.bootstrap_seconds = in.get<double>();
    const uint64_t saved_count = in.get<uint64_t>();
    if (saved_count == 0 || saved_count > (uint64_t(1) << 20))
      throw StateError("the saved chains do not fit this render (" + std::to_string(saved_count) +
                       " chains)");
    chain_count = int(saved_count);
    b_length = in.get_vector<double>(uint64_t(lengths));
    chains_of_length = in.get_vector<int32_t>(uint64_t(lengths));
    // A length has chains exactly when the bootstrap saw light in it, and they add up.
    int64_t given = 0;
    for (size_t k = 0; k < size_t(lengths); ++k) {
      if (!std::isfinite(b_length[k]) || b_length[k] < 0.0 || chains_of_length[k] < 0 ||
          (chains_of_length[k] > 0) != (b_length[k] > 0.0))
        throw StateError("the saved bootstrap is inconsistent");
      given += chains_of_length[k];
    }
    if (given != chain_count) throw StateError("the saved bootstrap is inconsistent");
  } else {
    // The chains' seeds: N independent samples (a large step each); MMLT gives sample i
    // the length min + i mod K, so every length gets N / K of them. Under MPI each rank
    // evaluates a share of the blocks and every rank gets every weight.
    const uint64_t samples = uint64_t(std::max(settings.bootstrap_samples, lengths));
    const auto length_of = [&](uint64_t i) {
      return multiplexed ? min_edges + int(i % uint64_t(lengths)) : 0;
    };
    const auto block_samples = [&](uint64_t block) { return samples * block / kBlocks; };
    std::vector<double> weights(samples, 0.0);
    const std::pair<uint64_t, uint64_t> own_blocks = cluster::share(kBlocks);
    arena.execute([&] {
      tbb::parallel_for(int(own_blocks.first), int(own_blocks.second), [&](int block) {
        PrimarySampleVector u(sigma);
        PssSample sample;
        for (uint64_t i = block_samples(uint64_t(block)); i < block_samples(uint64_t(block) + 1);
             ++i) {
          bootstrap_sample(tracer, settings.start_seed(), i, length_of(i), sigma, u, sample);
          weights[i] = std::isfinite(sample.target) ? sample.target : 0.0;
        }
      });
    });
    if (cluster::size() > 1) {
      StateWriter mine;
      mine.put_vector(std::vector<double>(weights.begin() + block_samples(own_blocks.first),
                                          weights.begin() + block_samples(own_blocks.second)));
      const std::vector<std::string_view> parts = cluster::gather_everywhere(mine.data());
      for (int r = 0; r < cluster::size(); ++r) {
        const auto [first, end] = cluster::share(kBlocks, r, cluster::size());
        StateReader in(parts[size_t(r)]);
        const std::vector<double> part =
            in.get_vector<double>(block_samples(end) - block_samples(first));
        std::copy(part.begin(), part.end(), weights.begin() + block_samples(first));
      }
    }
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
    bp.seed = settings.start_seed();
    bp.samples = settings.bootstrap_samples;
    bp.min_edges = min_edges;
    bp.max_edges = max_edges;
    bp.rr_depth = settings.rr_depth;
    bp.mis = settings.mis;
    bp.threads = threads;
    const Bootstrap path_bootstrap = run_bootstrap(scene, bp);
    // Every rank knows whether any rank's bootstrap was cut short (bootstrap.cpp).
    interruption::agree(path_bootstrap.interrupted);
    if (path_bootstrap.interrupted) {
      // Nothing of the bootstrap is kept: a resumed render runs it again, to the same bits.
      run.pause_before_chains();
      result.interrupted = true;
      result.stopped_in = "the bootstrap";
      result.seconds = stats_.seconds = elapsed();
      return result;
    }
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
      if (cluster::is_root())
        std::fprintf(stderr,
                     "emlt: warning: no bootstrap sample carries light; the MCMC part of the "
                     "image is black\n");
      run.finish_before_chains();
      result.seconds = stats_.seconds = elapsed();
      return result;
    }

    // Chains; for MMLT shared among the lengths in proportion to b_k, at least one for
    // every length the bootstrap saw light in (largest remainders, in length order).
    chain_count = settings.chains > 0
                      ? settings.chains
                      : MltIntegrator::default_chain_count(timed ? pixels * 16 : budget);
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
  }
  // b is the sum of the b_k, in length order (a resumed render sums the saved ones alike).
  double b = 0.0;
  for (const double b_k : b_length) b += b_k;
  if (!(b > 0.0) || !std::isfinite(b)) throw StateError("the saved bootstrap is inconsistent");
  stats_.b = b;

  std::vector<Chain> chains(static_cast<size_t>(chain_count));
  {
    size_t c = 0;
    for (size_t k = 0; k < size_t(lengths); ++k)
      for (int j = 0; j < chains_of_length[k]; ++j, ++c) {
        Chain& chain = chains[c];
        chain.u = PrimarySampleVector(sigma);
        chain.length = multiplexed ? min_edges + int(k) : 0;
        chain.b = b_length[k];
        chain.scale =
            multiplexed ? (b_length[k] / b) * double(chain_count) / chains_of_length[k] : 1.0;
        chain.rng = Rng::for_item(derive_stream_seed(settings.seed, kChainStream), c);
      }
  }
  // The chains run in a fixed partition of blocks; under MPI each rank runs a contiguous
  // share of them, so it holds one range of chains (the others' chains stay unseeded).
  const int block_count = std::min(chain_count, kBlocks);
  const auto first_chain_of = [&](uint64_t block) {
    return uint64_t(chain_count) * block / uint64_t(block_count);
  };
  const std::pair<uint64_t, uint64_t> owned_blocks = cluster::share(uint64_t(block_count));
  const uint64_t first_owned_block = owned_blocks.first, end_owned_block = owned_blocks.second;
  const uint64_t first_owned_chain = first_chain_of(first_owned_block),
                 end_owned_chain = first_chain_of(end_owned_block);
  if (!chain_in) {
    arena.execute([&] {
      tbb::parallel_for(int(first_owned_chain), int(end_owned_chain), [&](int c) {
        Chain& chain = chains[size_t(c)];
        const size_t k = multiplexed ? size_t(chain.length - min_edges) : 0;
        Rng seed_rng =
            Rng::for_item(derive_stream_seed(settings.start_seed(), kSeedStream), uint64_t(c));
        const double target = seed_rng.uniform_double() * cumulative[k].back();
        const size_t index =
            std::min(size_t(std::upper_bound(cumulative[k].begin(), cumulative[k].end(), target) -
                            cumulative[k].begin()),
                     pool[k].size() - 1);
        bootstrap_sample(tracer, settings.start_seed(), pool[k][index], chain.length, sigma, chain.u,
                         chain.current);
      });
    });
    stats_.bootstrap_seconds = elapsed() - bootstrap_start;
  }
  stats_.chains = uint64_t(chain_count);

  // Statistics, counted per block of chains: the step kinds, then the path lengths: for
  // MMLT the chain's, for PSSMLT the proposal's (its longest contributing path; a proposal
  // that carries no light counts under "no light"), so that every proposal counts once.
  stats_.strategy_names = {"large", "small"};
  for (int k = min_edges; k <= max_edges; ++k)
    stats_.strategy_names.push_back("length " + std::to_string(k));
  const size_t no_light_row = stats_.strategy_names.size();
  if (!multiplexed) stats_.strategy_names.push_back("no light");
  const size_t stat_count = stats_.strategy_names.size();
  struct alignas(64) BlockStats {
    std::vector<StrategyStats> stats;
  };
  std::vector<BlockStats> blocks(static_cast<size_t>(block_count));
  for (BlockStats& block : blocks) block.stats.assign(stat_count, StrategyStats{});
  std::vector<FixedPointFilm> films(size_t(std::min(threads, kMaxFilms)), FixedPointFilm(pixels));
  const bool shared_films = size_t(threads) > films.size();
  const PixelFilter& filter = camera.filter();

  // The schedule (see the sweeps below): the steps every chain has taken at the end of the
  // last whole sweep, the sweep under way (each chain takes steps up to sweep_end), the
  // timed sweeps' rounds, and the steps of the log's last row.
  const uint64_t planned_steps =
      timed ? (settings.mutations_per_pixel > 0
                   ? (budget + uint64_t(chain_count) - 1) / uint64_t(chain_count)
                   : UINT64_MAX)
            : (budget + uint64_t(chain_count) - 1) / uint64_t(chain_count);
  uint64_t steps_done = 0, sweep_end = 0, rounds = 1;
  uint64_t logged = UINT64_MAX;  // the steps of the log's last row
  uint8_t sweep_active = 0;
  std::vector<uint64_t> chain_steps(static_cast<size_t>(chain_count), 0);
  if (chain_in) {
    StateReader& in = *chain_in;
    const uint64_t first = in.get<uint64_t>(), end = in.get<uint64_t>();
    if (first != first_owned_chain || end != end_owned_chain)
      throw StateError("the saved chains are not this process's share of them");
    for (uint64_t c = first; c < end; ++c) {
      Chain& chain = chains[size_t(c)];
      chain.u.load(in);
      chain.current.target = in.get<double>();
      chain.current.splats = in.get_vector_up_to<PssSplat>(kMaxSplats);
      chain.carried = in.get<double>();
      chain.rng = Rng::restore(in.get<Rng::State>());
      chain_steps[size_t(c)] = in.get<uint64_t>();
      // A chain's state was accepted, so f* > 0; its splats land on the film (their colours
      // are non-negative: the film turns them into integers assuming so).
      bool consistent = std::isfinite(chain.current.target) && chain.current.target > 0.0 &&
                        std::isfinite(chain.carried) && chain.carried >= 0.0;
      for (const PssSplat& s : chain.current.splats)
        consistent = consistent && s.raster.x >= 0.0f && s.raster.x <= float(width) &&
                     s.raster.y >= 0.0f && s.raster.y <= float(height) &&
                     std::isfinite(s.value.x) && s.value.x >= 0.0f && std::isfinite(s.value.y) &&
                     s.value.y >= 0.0f && std::isfinite(s.value.z) && s.value.z >= 0.0f;
      if (!consistent) throw StateError("a saved chain is inconsistent");
    }
    for (BlockStats& block : blocks)
      for (StrategyStats& stats : block.stats) stats = in.get<StrategyStats>();
    const std::vector<int64_t> units = in.get_vector<int64_t>(3 * pixels);
    for (const int64_t u : units)
      if (u < 0) throw StateError("the saved film is inconsistent");
    FixedPointFilm::load_units(films, units);
    steps_done = in.get<uint64_t>();
    sweep_active = in.get<uint8_t>();
    sweep_end = in.get<uint64_t>();
    rounds = in.get<uint64_t>();
    logged = in.get<uint64_t>();
    in.expect_end();
    // Every count that steers the loop is checked, so that a damaged state can neither
    // loop (nearly) forever nor promise a chain steps it cannot take.
    // (2^40 steps per chain: weeks of rendering; a bound that keeps steps x chains in range.)
    bool consistent = sweep_active <= 1 && rounds > 0 && (rounds & (rounds - 1)) == 0 &&
                      rounds <= (uint64_t(1) << 40) && steps_done <= (uint64_t(1) << 40);
    if (consistent && sweep_active)
      consistent = sweep_end > steps_done && sweep_end <= planned_steps &&
                   (!timed || sweep_end - steps_done <= rounds);
    for (uint64_t c = first; consistent && c < end; ++c)
      consistent = sweep_active
                       ? chain_steps[size_t(c)] >= steps_done && chain_steps[size_t(c)] <= sweep_end
                       : chain_steps[size_t(c)] == steps_done;
    if (!consistent) throw StateError("the saved chains' schedule is inconsistent");
    const uint64_t committed = sweep_active ? sweep_end : steps_done;
    if (!timed && committed > planned_steps)
      throw StateError("the checkpoint has " + std::to_string(committed) +
                       " steps per chain done or under way, more than this run's budget of " +
                       std::to_string(planned_steps) +
                       " (a resumed render may extend the budget, not cut it)");
    chain_in.reset();
    chain_section.clear();
  }
  const auto owns_block = [&](uint64_t block) {
    return block >= first_owned_block && block < end_owned_block;
  };

  const auto save_chains = [&](StateWriter& out) {
    out.put<double>(stats_.b_standard_error);
    out.put<uint64_t>(stats_.bootstrap_samples);
    out.put<double>(stats_.bootstrap_seconds);
    out.put<uint64_t>(uint64_t(chain_count));
    out.put_vector(b_length);
    out.put_vector(chains_of_length);
    out.put<uint64_t>(first_owned_chain);
    out.put<uint64_t>(end_owned_chain);
    for (uint64_t c = first_owned_chain; c < end_owned_chain; ++c) {
      const Chain& chain = chains[size_t(c)];
      chain.u.save(out);
      out.put<double>(chain.current.target);
      out.put_vector(chain.current.splats);
      out.put<double>(chain.carried);
      out.put(chain.rng.save());
      out.put<uint64_t>(chain_steps[size_t(c)]);
    }
    for (const BlockStats& block : blocks)
      for (const StrategyStats& stats : block.stats) out.put<StrategyStats>(stats);
    std::vector<int64_t> units;
    if (!FixedPointFilm::total_units(films, units))
      throw Error("the MCMC film overflowed: too many mutations' worth of weight in one pixel");
    out.put_vector(units);
    out.put<uint64_t>(steps_done);
    out.put<uint8_t>(sweep_active);
    out.put<uint64_t>(sweep_end);
    out.put<uint64_t>(rounds);
    out.put<uint64_t>(logged);
  };
  const auto save_all = [&](StateWriter& out) { run.save(out, save_chains); };

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
    const int length = multiplexed ? chain.length : proposal.target > 0.0 ? proposal.length : 0;
    StrategyStats& length_stats =
        stats[length >= min_edges && length <= max_edges ? 2 + size_t(length - min_edges)
                                                         : no_light_row];
    ++length_stats.proposed;
    length_stats.acceptance_sum += a;
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
      ++length_stats.accepted;
    } else {
      chain.u.reject(options_.keep_coordinate_on_reject);
    }
  };

  // The image after `done` steps: the films plus every chain's weight not yet splatted
  // (added to a copy), scaled by pixels b / steps. Under MPI, on rank 0: each rank adds its
  // own chains' films and weights, and the integer sums are added over the ranks.
  const Image direct_image = result.image;
  const auto compose = [&](uint64_t done) {
    std::vector<FixedPointFilm> total(1, FixedPointFilm(pixels));
    std::vector<int64_t> units;
    if (!FixedPointFilm::total_units(films, units))
      throw Error("the MCMC film overflowed: too many mutations' worth of weight in one pixel");
    FixedPointFilm::load_units(total, units);
    for (uint64_t c = first_owned_chain; c < end_owned_chain; ++c) {
      const Chain& chain = chains[size_t(c)];
      splat(total[0], false, filter, width, height, chain.current, chain.carried * chain.scale,
            chain.current.target + p_large * chain.b);
    }
    if (!FixedPointFilm::total_units(total, units))
      throw Error("the MCMC film overflowed: too many mutations' worth of weight in one pixel");
    cluster::sum_to_root(units);
    const double scale = done > 0 ? double(pixels) * b / double(done) : 0.0;
    Image image = direct_image;
    for (uint64_t p = 0; p < pixels; ++p)
      image.pixels[p] +=
          Rgb(DVec3(double(units[3 * p]), double(units[3 * p + 1]), double(units[3 * p + 2])) *
              (scale / FixedPointFilm::kUnitsPerValue));
    return image;
  };
  // Every block's counters, merged in block order, on rank 0 (a block's are its owner's;
  // the other ranks hold zeros).
  const auto merged_stats = [&] {
    std::vector<uint64_t> counts;
    std::vector<double> sums;
    for (const BlockStats& block : blocks)
      for (const StrategyStats& st : block.stats) {
        counts.insert(counts.end(),
                      {st.proposed, st.not_applicable, st.failed, st.accepted, st.fallbacks});
        sums.push_back(st.acceptance_sum);
      }
    cluster::sum_to_root(counts);
    cluster::sum_to_root(sums);
    std::vector<StrategyStats> out(stat_count);
    for (size_t b = 0, k = 0; b < blocks.size(); ++b)
      for (size_t i = 0; i < stat_count; ++i, ++k) {
        StrategyStats st;
        st.proposed = counts[5 * k], st.not_applicable = counts[5 * k + 1];
        st.failed = counts[5 * k + 2], st.accepted = counts[5 * k + 3];
        st.fallbacks = counts[5 * k + 4], st.acceptance_sum = sums[k];
        out[i].merge(st);
      }
    return out;
  };
  const auto acceptance_so_far = [&] {
    const std::vector<StrategyStats> merged = merged_stats();
    std::vector<StrategyAcceptance> out;
    for (size_t i = 0; i < stat_count; ++i)
      out.push_back({stats_.strategy_names[i], merged[i].mean_acceptance()});
    return out;
  };
  // Under MPI, rank 0's clock decides the time budget for every rank (a broadcast).
  const auto root_decides = [&](uint64_t& value) {
    if (cluster::size() == 1 || !timed) return;
    StateWriter out;
    out.put(value);
    std::string data = out.take();
    cluster::broadcast(data);
    value = StateReader(data).get<uint64_t>();
  };

  // Sweeps: every chain takes the same number of steps, so that MMLT's per-length scale is
  // exact. A budget of mutations is rounded up to whole steps per chain and split at
  // powers of two in mutations per pixel (the log's snapshots); a time budget runs sweeps
  // of `rounds` steps per chain, doubled while a sweep takes under 50 ms. A chain's steps
  // depend on its own state alone and the films add integers, so the image depends on how
  // many steps each chain took, not on how the sweeps were cut: a pause (a checkpoint
  // falling due, a stop) cuts a sweep short, with every chain's steps recorded, and the
  // sweep then goes on from there, in this process or a resumed one.
  uint64_t own_steps = 0;
  for (uint64_t c = first_owned_chain; c < end_owned_chain; ++c)
    own_steps += chain_steps[size_t(c)];
  progress.start(name().c_str(), timed ? 0 : planned_steps * uint64_t(chain_count),
                 settings.time_limit_s);
  progress.advance(own_steps);
  // The next power of two in mutations per pixel, after the steps done.
  uint64_t next_snapshot = 1;
  while (steps_done * uint64_t(chain_count) >= next_snapshot * pixels) next_snapshot *= 2;
  bool stopped = false;
  while (true) {
    if (!sweep_active) {
      if (steps_done >= planned_steps) break;
      // (At least one sweep: a budget spent by the bootstrap still gives the chains a round.)
      uint64_t time_up = timed && steps_done > 0 && run.counted_seconds() >= settings.time_limit_s;
      root_decides(time_up);
      if (time_up) break;
      uint64_t sweep = timed ? rounds : planned_steps - steps_done;
      sweep = std::min(sweep, planned_steps - steps_done);
      // Up to the next power of two in mutations per pixel.
      const uint64_t snapshot_steps =
          (next_snapshot * pixels + uint64_t(chain_count) - 1) / uint64_t(chain_count);
      if (snapshot_steps > steps_done) sweep = std::min(sweep, snapshot_steps - steps_done);
      sweep_end = steps_done + sweep;
      sweep_active = 1;
    }
    const double sweep_start = elapsed();
    arena.execute([&] {
      tbb::parallel_for(0, block_count, [&](int block) {
        if (!owns_block(uint64_t(block))) return;
        const size_t slot =
            size_t(std::max(tbb::this_task_arena::current_thread_index(), 0)) % films.size();
        PssSample proposal;
        uint64_t block_steps = 0;
        for (uint64_t c = first_chain_of(uint64_t(block)); c < first_chain_of(uint64_t(block) + 1);
             ++c) {
          Chain& chain = chains[size_t(c)];
          uint64_t& taken = chain_steps[size_t(c)];
          const uint64_t before = taken;
          for (; taken < sweep_end; ++taken) {
            if ((taken & 255) == 255 && interruption::requested()) break;
            step(chain, proposal, films[slot], blocks[size_t(block)].stats);
          }
          block_steps += taken - before;
          if (interruption::poll(taken - before)) break;
        }
        progress.advance(block_steps);
      });
    });
    bool incomplete = false;
    for (uint64_t c = first_owned_chain; c < end_owned_chain; ++c)
      incomplete |= chain_steps[size_t(c)] < sweep_end;
    // Every rank takes the same decision at the same point (interruption.h).
    const interruption::Decision decision = interruption::agree(incomplete);
    if (!decision.incomplete) {
      sweep_active = 0;
      steps_done = sweep_end;
      if (timed && elapsed() - sweep_start < std::min(0.05, settings.time_limit_s / 50.0))
        rounds *= 2;
      root_decides(rounds);
      for (; steps_done * uint64_t(chain_count) >= next_snapshot * pixels; next_snapshot *= 2)
        if (settings.snapshots && steps_done * uint64_t(chain_count) != logged) {
          const auto begin = std::chrono::steady_clock::now();
          const uint64_t done = steps_done * uint64_t(chain_count);
          logged = done;
          settings.snapshots->snapshot(double(done) / double(pixels), run.counted_seconds(),
                                       compose(done), acceptance_so_far());
          run.write_off(
              std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
        }
    }
    if (decision.pause()) {
      RenderControl::pause(control, save_all);
      if (decision.stop && (decision.incomplete || steps_done < planned_steps)) {
        stopped = true;
        break;
      }
    }
  }
  progress.finish();
  // A stop mid-sweep leaves chains with different step counts: the image then counts the
  // steps actually taken (exact for PSSMLT; MMLT's per-length scale assumes equal counts).
  std::vector<uint64_t> done_steps = {0};
  for (uint64_t c = first_owned_chain; c < end_owned_chain; ++c)
    done_steps[0] += chain_steps[size_t(c)];
  cluster::sum_everywhere(done_steps);
  const uint64_t done = done_steps[0];
  result.image = compose(done);
  // The log ends on the final image unless its last row already is that image.
  if (settings.snapshots && done != logged) {
    settings.snapshots->snapshot(double(done) / double(pixels), run.counted_seconds(), result.image,
                                 acceptance_so_far());
    logged = done;
  }
  if (!stopped) RenderControl::finish(control, save_all);
  result.interrupted = stopped;
  if (stopped) result.stopped_in = "the chains";
  stats_.strategies = merged_stats();
  stats_.mutations = done;
  stats_.seconds = run.counted_seconds();
  result.seconds = stats_.seconds;
  result.samples = done;
  result.samples_per_pixel = int(std::llround(double(done) / double(pixels)));
  result.per_pixel = double(done) / double(pixels);
  return result;
}

}  // namespace emlt
