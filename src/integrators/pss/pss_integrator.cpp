#include "emlt/integrators/pss/pss_integrator.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/mlt/bootstrap.h"
#include "emlt/integrators/mlt/mcmc_run.h"
#include "emlt/integrators/pss/pss_chains.h"

namespace emlt {

namespace {

constexpr uint64_t kBootstrapStream = 0xb5500ull << 40;
constexpr uint64_t kSeedStream = 0x55eedull << 40;
// The bootstrap's samples are evaluated in a fixed partition of blocks, which MPI shares
// among the ranks as it shares the chains' blocks.
constexpr int kBlocks = 64;

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
  // The clock (with the runs before a resume), the checkpoint state and the direct pass.
  McmcRun run(scene, settings);
  const uint64_t pixels = run.pixels();
  const bool multiplexed = options_.multiplexed;
  const float sigma = float(settings.pss_sigma);
  stats_ = MltStatistics{};

  const int min_edges = settings.direct_separate ? 3 : settings.shortest_path();
  const int max_edges = settings.max_depth < 0 ? BidirectionalPathTracer::kUnlimitedDepth
                                               : std::min(settings.max_depth, kMaxPathVertices - 1);

  // A resumed render's chains (mcmc_run.h).
  std::string& chain_section = run.chain_section();

  RenderResult result = run.black_result();
  if (min_edges > max_edges) {
    run.end_without_chains(result, stats_);
    return result;
  }
  const PssTracer kind = multiplexed         ? PssTracer::Multiplexed
                         : settings.pss_bdpt ? PssTracer::Bdpt
                                             : PssTracer::PathTracer;
  const PrimarySampleTracer tracer(scene, settings, kind, min_edges, max_edges,
                                   options_.ignore_technique_selection);
  const int threads = ChainSweeper::thread_count(settings);
  tbb::task_arena arena(threads);
  const bool timed = settings.time_limit_s > 0.0;
  const uint64_t budget =
      uint64_t(std::llround(std::max(settings.mutations_per_pixel, 0.0) * double(pixels)));
  const int lengths = multiplexed ? max_edges - min_edges + 1 : 1;

  // What the bootstrap decides: b_k for every length (b for PSSMLT) and how many chains
  // each length has. A resumed render takes them from its checkpoint, with the chain count
  // (the default depends on the budget, which a resumed run may extend).
  PssBootstrap boot;
  boot.b_length.assign(static_cast<size_t>(lengths), 0.0);
  boot.chains_of_length.assign(static_cast<size_t>(lengths), 0);
  boot.seeds.assign(static_cast<size_t>(lengths), NormalisationSums{});
  std::vector<double>& b_length = boot.b_length;
  std::vector<int32_t>& chains_of_length = boot.chains_of_length;
  int& chain_count = boot.chain_count;
  std::optional<StateReader> chain_in;
  const BootstrapParams bp = BootstrapParams::of(settings, min_edges, max_edges, threads);
  Bootstrap path_bootstrap;  // a fresh render's
  // Fresh: the pool of each length's bootstrap samples (in sample order) with their
  // cumulative f*, for the chains' seeds.
  std::vector<std::vector<uint64_t>> pool(static_cast<size_t>(lengths));
  std::vector<std::vector<double>> cumulative(static_cast<size_t>(lengths));
  const double bootstrap_start = run.elapsed();
  if (!chain_section.empty()) {
    if (run.control() && run.control()->resume_format() < kPssChainsOldestFormat)
      throw StateError("this " + name() + " checkpoint of format " +
                       std::to_string(run.control()->resume_format()) +
                       " holds the chains' film in a form this emlt no longer splits; render "
                       "again from the start");
    if (multiplexed && run.control() && run.control()->resume_format() < kMmltChainsOldestFormat)
      throw StateError("this mmlt checkpoint of format " +
                       std::to_string(run.control()->resume_format()) +
                       " lacks the BDPT samples its b is now made of; render again from the start");
    chain_in.emplace(chain_section);
    boot.load(*chain_in, lengths, stats_);
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
    // The seeds' f* in sample order: the first of the converging b's samples.
    for (uint64_t i = 0; i < samples; ++i) {
      const size_t k = multiplexed ? size_t(i % uint64_t(lengths)) : 0;
      boot.seeds[k].add(weights[i]);
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
    path_bootstrap = run_bootstrap(scene, bp);
    if (run.stopped_in_bootstrap(path_bootstrap.interrupted, result, stats_)) return result;
    for (const BootstrapCandidate& c : path_bootstrap.candidates) {
      const int k = multiplexed ? int(c.s) + int(c.t) - 1 - min_edges : 0;
      if (k >= 0 && k < lengths) b_length[size_t(k)] += double(c.weight);
    }
    double b = 0.0;
    for (size_t k = 0; k < size_t(lengths); ++k) {
      b_length[k] = b_length[k] / double(path_bootstrap.samples) * options_.bootstrap_b_factor;
      // A length without a seed cannot have a chain (nor, in practice, light).
      if (pool[k].empty()) b_length[k] = 0.0;
      b += b_length[k];
    }
    stats_.b = b;
    stats_.b_standard_error = boot.standard_error = path_bootstrap.standard_error;
    stats_.bootstrap_samples = path_bootstrap.samples;
    if (!(b > 0.0)) {
      stats_.bootstrap_seconds = run.elapsed() - bootstrap_start;
      run.end_without_chains(
          result, stats_, "no bootstrap sample carries light; the MCMC part of the image is black");
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
  const double b = boot.b();
  if (!(b > 0.0) || !std::isfinite(b)) throw StateError("the saved bootstrap is inconsistent");
  // The weights' b; the chains' part of the image is scaled by the b of the primary samples
  // (pss_normalisation.h), which the chains' images fill in.
  stats_.b = stats_.bootstrap_b = b;
  stats_.b_samples = stats_.bootstrap_samples;

  std::optional<NormalisationPass> normalisation;
  if (multiplexed && !options_.mmlt_b_from_large_steps_only) {
    normalisation.emplace(scene, bp, settings.normalisation_rate);
    std::vector<bool> counted;
    for (const int32_t chains : boot.chains_of_length) counted.push_back(chains > 0);
    normalisation->split_by_length(std::move(counted));
    if (!chain_in) normalisation->start(path_bootstrap);
  }
  path_bootstrap = {};
  PssChains pss(PssSetup{scene, settings, tracer, options_, min_edges, max_edges, std::move(boot),
                         std::move(normalisation)},
                run, progress, stats_, chain_in ? &*chain_in : nullptr);
  if (!chain_in) {
    std::vector<PssChain>& chains = pss.chains();
    // (Not a structured binding: clang 14, the fuzz build's compiler, cannot capture one.)
    const std::pair<uint64_t, uint64_t> owned = pss.owned_chains();
    pss.arena().execute([&] {
      tbb::parallel_for(int(owned.first), int(owned.second), [&](int c) {
        PssChain& chain = chains[size_t(c)];
        const size_t k = multiplexed ? size_t(chain.length - min_edges) : 0;
        Rng seed_rng =
            Rng::for_item(derive_stream_seed(settings.start_seed(), kSeedStream), uint64_t(c));
        const double target = seed_rng.uniform_double() * cumulative[k].back();
        const size_t index =
            std::min(size_t(std::upper_bound(cumulative[k].begin(), cumulative[k].end(), target) -
                            cumulative[k].begin()),
                     pool[k].size() - 1);
        bootstrap_sample(tracer, settings.start_seed(), pool[k][index], chain.length, sigma,
                         chain.u, chain.current);
      });
    });
    stats_.bootstrap_seconds = run.elapsed() - bootstrap_start;
  }
  chain_in.reset();
  chain_section.clear();
  result = pss.render(name());
  run.direct_statistics(stats_);
  stats_.seconds = result.seconds;
  return result;
}

}  // namespace emlt
