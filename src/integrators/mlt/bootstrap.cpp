#include "emlt/integrators/mlt/bootstrap.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "emlt/core/cluster.h"
#include "emlt/core/interruption.h"
#include "emlt/core/state_io.h"
#include "emlt/path/connection.h"
#include "emlt/path/random_walk.h"

namespace emlt {

namespace {

constexpr uint64_t kBootstrapStream = 0xb0075ull << 40;

struct SampleScratch {
  PathVertices light, camera;
  VertexDensity densities[kMaxPathVertices];
};

// The two subpaths of a sample whose camera subpath starts at `raster`, drawn from `rng`,
// which is left where the strategies' own draws begin.
void generate_subpaths_at(const Scene& scene, const BootstrapParams& p, Rng& rng,
                          const Vec2& raster, SampleScratch& scratch) {
  const Vec2 u_lens = rng.uniform2();
  generate_camera_subpath(scene, rng, raster, u_lens,
                          {p.max_edges + 1, subpath_rr_depth(p.rr_depth)}, scratch.camera);
  generate_light_subpath(scene, rng, {p.max_edges, subpath_rr_depth(p.rr_depth)}, scratch.light);
}

// A bootstrap sample's two subpaths, from the start of its stream (its raster uniform over
// the image); `rng` is left where the strategies' own draws begin.
Rng generate_subpaths(const Scene& scene, const BootstrapParams& p, uint32_t sample,
                      SampleScratch& scratch) {
  Rng rng(derive_stream_seed(p.seed, kBootstrapStream + sample), sample);
  const Camera& camera = scene.camera();
  const Vec2 raster(rng.uniform() * float(camera.width()), rng.uniform() * float(camera.height()));
  generate_subpaths_at(scene, p, rng, raster, scratch);
  return rng;
}

// Every strategy of one bidirectional sample whose subpaths are in `scratch`, in a fixed
// order that consumes `rng` identically each time. The only draws after the subpaths are the
// lens points of the t = 1 strategies, one pair each for s = 0, 1, ... (rebuild_candidate
// relies on it).
void enumerate_strategies(const Scene& scene, const BootstrapParams& p, Rng& rng,
                          SampleScratch& scratch, const StrategyVisitor& visit) {
  const auto& cam = scratch.camera;
  const auto& light = scratch.light;

  for (int t = 1; t <= int(cam.size()); ++t) {
    for (int s = 0; s <= int(light.size()); ++s) {
      const int segments = s + t - 1;
      if (segments > p.max_edges) break;
      // Drawn whether or not the strategy is used, so replay stays in step.
      const Vec2 u_connect = t == 1 ? rng.uniform2() : Vec2(0.0f);
      if (segments < p.min_edges) continue;
      Rgb contribution(0.0f);
      PathVertex lens;
      std::span<const PathVertex> camera_side(cam);
      if (s == 0) {
        const PathVertex& z = cam[size_t(t - 1)];
        if (t < 2 || !z.is_emitter()) continue;
        contribution = z.throughput * vertex_factor(scene, z, nullptr, &cam[size_t(t - 2)]);
      } else {
        const PathVertex& y = light[size_t(s - 1)];
        const PathVertex* y_previous = s >= 2 ? &light[size_t(s - 2)] : nullptr;
        if (t == 1) {
          const auto sampled = sample_camera_vertex(scene, y, u_connect);
          if (!sampled) continue;
          lens = *sampled;
          camera_side = std::span<const PathVertex>(&lens, 1);
          contribution = y.throughput * connect_vertices(scene, y_previous, y, lens, nullptr) *
                         lens.throughput;
        } else {
          const PathVertex& z = cam[size_t(t - 1)];
          contribution = y.throughput *
                         connect_vertices(scene, y_previous, y, z, &cam[size_t(t - 2)]) *
                         z.throughput;
        }
      }
      if (is_black(contribution) || !is_finite(contribution)) continue;
      const std::span<VertexDensity> densities(scratch.densities, size_t(s + t));
      connection_densities(scene, light, s, camera_side, t, densities);
      contribution *= float(mis_weight(densities, s, p.mis));
      if (is_black(contribution) || !is_finite(contribution)) continue;
      if (!visit(s, t, contribution, light, camera_side)) return;
    }
  }
}

// Every strategy of bootstrap sample `sample`.
void enumerate_sample(const Scene& scene, const BootstrapParams& p, uint32_t sample,
                      SampleScratch& scratch, const StrategyVisitor& visit) {
  Rng rng = generate_subpaths(scene, p, sample, scratch);
  enumerate_strategies(scene, p, rng, scratch, visit);
}

}  // namespace

void enumerate_sample_at(const Scene& scene, const BootstrapParams& params, Rng& rng,
                         const Vec2& raster, const StrategyVisitor& visit) {
  thread_local SampleScratch scratch;
  generate_subpaths_at(scene, params, rng, raster, scratch);
  enumerate_strategies(scene, params, rng, scratch, visit);
}

size_t Bootstrap::choose(double u) const {
  const double target = u * cumulative.back();
  const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
  return std::min(size_t(it - cumulative.begin()), candidates.size() - 1);
}

double Bootstrap::effective_candidates() const {
  double sum = 0.0, sum_squares = 0.0;
  for (const BootstrapCandidate& c : candidates) {
    sum += c.weight;
    sum_squares += double(c.weight) * double(c.weight);
  }
  return sum_squares > 0.0 ? sum * sum / sum_squares : 0.0;
}

void grow_bootstrap(const Scene& scene, const BootstrapParams& p, uint64_t total, Bootstrap& pool) {
  if (total <= pool.samples) return;
  if (total > uint64_t(UINT32_MAX)) throw std::invalid_argument("bootstrap: too many samples");
  // Samples [start, total) in 64 blocks of consecutive samples, merged in block order after
  // the pool's own: the candidates then sit in sample order, as one run over [0, total).
  const uint64_t start = pool.samples, count = total - start;
  const int blocks = 64;
  // A line each: neighbouring blocks run on different threads, and each sample writes its
  // block's sums and the pool's end pointer.
  struct alignas(64) Block {
    std::vector<BootstrapCandidate> candidates;
    double sum = 0.0, sum_squares = 0.0, largest = 0.0;
  };
  std::vector<Block> results(blocks);
  std::atomic<bool> interrupted{false};
  const int threads = p.threads > 0 ? p.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  // Under MPI each rank samples its share of the blocks and the blocks are then exchanged,
  // so that every rank holds the whole pool, summed in block order (cluster.h).
  // (Not a structured binding: clang 14, the fuzz build's compiler, cannot capture one.)
  const std::pair<uint64_t, uint64_t> owned = cluster::share(uint64_t(blocks));
  const uint64_t first_block = owned.first, last_block = owned.second;
  arena.execute([&] {
    tbb::parallel_for(int(first_block), int(last_block), [&](int block) {
      SampleScratch scratch;
      Block& out = results[size_t(block)];
      const uint32_t first = uint32_t(start + count * uint64_t(block) / blocks);
      const uint32_t last = uint32_t(start + count * uint64_t(block + 1) / blocks);
      for (uint32_t sample = first; sample < last; ++sample) {
        // A stop signal abandons the bootstrap (it is rerun on resume); a checkpoint falling
        // due waits for it, as it takes seconds at most.
        if (interruption::stop_requested()) {
          interrupted = true;
          break;
        }
        double sample_total = 0.0;
        enumerate_sample(scene, p, sample, scratch, [&](int s, int t, const Rgb& c, auto, auto) {
          const float weight = luminance(c);
          if (weight > 0.0f) {
            out.candidates.push_back({sample, uint8_t(s), uint8_t(t), weight});
            sample_total += weight;
          }
          return true;
        });
        out.sum += sample_total;
        out.sum_squares += sample_total * sample_total;
        out.largest = std::max(out.largest, sample_total);
      }
    });
  });

  Bootstrap& result = pool;
  bool any_interrupted = interrupted.load();
  if (cluster::size() > 1) {
    StateWriter mine;
    mine.put<uint8_t>(any_interrupted);
    for (uint64_t b = first_block; b < last_block; ++b) {
      mine.put<uint64_t>(b);
      mine.put(results[b].sum);
      mine.put(results[b].sum_squares);
      mine.put(results[b].largest);
      mine.put_vector(results[b].candidates);
    }
    for (const std::string_view part : cluster::gather_everywhere(mine.data())) {
      StateReader in(part);
      any_interrupted |= in.get<uint8_t>() != 0;
      while (in.remaining() > 0) {
        Block& block = results.at(in.get<uint64_t>());
        block.sum = in.get<double>();
        block.sum_squares = in.get<double>();
        block.largest = in.get<double>();
        block.candidates =
            in.get_vector_up_to<BootstrapCandidate>(UINT64_MAX / sizeof(BootstrapCandidate));
      }
    }
  }
  result.interrupted |= any_interrupted;
  result.samples = total;
  size_t added = 0;
  for (const Block& block : results) added += block.candidates.size();
  // Reserved: grown one candidate at a time, this serial merge of the Cornell box's 880,000
  // candidates took 0.027-0.030 s on the 2-core machine; reserved, 0.013-0.014 s in two runs
  // of three (the whole bootstrap took 0.09 s at 16 threads on a lent 16-core machine).
  result.candidates.reserve(result.candidates.size() + added);
  result.cumulative.reserve(result.cumulative.size() + added);
  double sum = result.sum, sum_squares = result.sum_squares;
  double running = result.cumulative.empty() ? 0.0 : result.cumulative.back();
  for (Block& block : results) {  // block order: the same pool at any thread count
    sum += block.sum;
    sum_squares += block.sum_squares;
    result.largest_sample = std::max(result.largest_sample, block.largest);
    result.candidates.insert(result.candidates.end(), block.candidates.begin(),
                             block.candidates.end());
    for (const BootstrapCandidate& c : block.candidates) {
      running += c.weight;
      result.cumulative.push_back(running);
    }
    block.candidates = {};
  }
  result.sum = sum;
  result.sum_squares = sum_squares;
  if (result.samples > 0) {
    const double n = double(result.samples);
    result.b = sum / n;
    result.standard_error = std::sqrt(std::max(sum_squares / n - result.b * result.b, 0.0) / n);
  }
}

void bootstrap_sample_totals(const Scene& scene, const BootstrapParams& p, uint32_t first,
                             uint32_t last, const std::function<void(double)>& each) {
  SampleScratch scratch;
  for (uint32_t sample = first; sample < last; ++sample) {
    double total = 0.0;
    enumerate_sample(scene, p, sample, scratch, [&](int, int, const Rgb& c, auto, auto) {
      const float weight = luminance(c);
      if (weight > 0.0f) total += weight;
      return true;
    });
    each(total);
  }
}

void bootstrap_sample_lengths(const Scene& scene, const BootstrapParams& p, uint32_t first,
                              uint32_t last,
                              const std::function<void(std::span<const double>)>& each) {
  SampleScratch scratch;
  std::vector<double> by_length(size_t(std::max(p.max_edges - p.min_edges + 1, 0)));
  for (uint32_t sample = first; sample < last; ++sample) {
    std::fill(by_length.begin(), by_length.end(), 0.0);
    enumerate_sample(scene, p, sample, scratch, [&](int s, int t, const Rgb& c, auto, auto) {
      const float weight = luminance(c);
      const int k = s + t - 1 - p.min_edges;
      if (weight > 0.0f && k >= 0 && k < int(by_length.size())) by_length[size_t(k)] += weight;
      return true;
    });
    each(by_length);
  }
}

Bootstrap run_bootstrap(const Scene& scene, const BootstrapParams& p) {
  Bootstrap pool;
  grow_bootstrap(scene, p, uint64_t(std::max(p.samples, 0)), pool);
  return pool;
}

uint64_t grown_bootstrap_samples(uint64_t samples, double effective, uint64_t chains,
                                 uint64_t cap) {
  const double wanted_effective = 2.0 * double(chains);
  if (samples == 0 || !(effective > 0.0) || effective >= wanted_effective || cap <= samples)
    return samples;
  // The pool's worth grows in proportion to its samples (they are independent).
  const double wanted = std::ceil(double(samples) * wanted_effective / effective);
  return wanted >= double(cap) ? cap : std::max(samples, uint64_t(wanted));
}

uint64_t bootstrap_time_cap(uint64_t samples, double time_limit_s, double first_round_seconds) {
  if (!(time_limit_s > 0.0)) return UINT64_MAX;
  const double figure = double(samples) * 0.2 * time_limit_s / std::max(first_round_seconds, 1e-3);
  return figure >= double(UINT64_MAX) ? UINT64_MAX : uint64_t(figure);
}

uint64_t bootstrap_growth_cap(uint64_t samples, size_t candidates, uint64_t planned_mutations,
                              uint64_t time_cap) {
  uint64_t cap = std::min<uint64_t>(16 * samples, uint64_t(UINT32_MAX));
  if (planned_mutations != UINT64_MAX) cap = std::min(cap, planned_mutations / 32);
  cap = std::min(cap, time_cap);
  constexpr double kMostCandidates = 4e6;
  if (candidates > 0)
    cap = std::min(cap, uint64_t(double(samples) * kMostCandidates / double(candidates)));
  return std::max(cap, samples);
}

std::optional<Path> rebuild_candidate_by_enumeration(const Scene& scene,
                                                     const BootstrapParams& params,
                                                     const BootstrapCandidate& candidate) {
  SampleScratch scratch;
  std::optional<Path> path;
  enumerate_sample(scene, params, candidate.sample, scratch,
                   [&](int s, int t, const Rgb&, std::span<const PathVertex> light,
                       std::span<const PathVertex> camera_side) {
                     if (s != candidate.s || t != candidate.t) return true;
                     Path p;
                     if (join_subpaths(scene, light, s, camera_side, t, p)) {
                       recompute_densities(scene, p);
                       path = std::move(p);
                     }
                     return false;
                   });
  return path;
}

std::optional<Path> rebuild_candidate(const Scene& scene, const BootstrapParams& params,
                                      const BootstrapCandidate& candidate) {
  // Straight to the candidate's strategy: its subpaths, then (for t = 1) the lens point that
  // enumerate_sample drew for it after those of s' = 0 .. s - 1. The pool only holds
  // strategies that enumeration reached and found non-zero, so nothing else is re-checked;
  // replaying the whole enumeration cost a sample's every connection per chain.
  SampleScratch scratch;
  Rng rng = generate_subpaths(scene, params, candidate.sample, scratch);
  const int s = candidate.s, t = candidate.t;
  if (t < 1 || t > int(scratch.camera.size()) || s > int(scratch.light.size())) return std::nullopt;
  std::span<const PathVertex> camera_side(scratch.camera);
  PathVertex lens;
  if (t == 1) {
    if (s == 0) return std::nullopt;
    for (int skipped = 0; skipped < s; ++skipped) rng.uniform2();
    const auto sampled = sample_camera_vertex(scene, scratch.light[size_t(s - 1)], rng.uniform2());
    if (!sampled) return std::nullopt;
    lens = *sampled;
    camera_side = std::span<const PathVertex>(&lens, 1);
  }
  Path path;
  if (!join_subpaths(scene, scratch.light, s, camera_side, t, path)) return std::nullopt;
  recompute_densities(scene, path);
  return path;
}

}  // namespace emlt
