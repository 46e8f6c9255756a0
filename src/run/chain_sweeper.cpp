#include "emlt/run/chain_sweeper.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/run/render_control.h"
#include "emlt/run/snapshot.h"

namespace emlt {

namespace {
// More threads than this share films (atomic additions): a film per thread costs memory of
// the image's size each, and their sum is taken at every snapshot and checkpoint. Films of
// several layers count as that many films, so the memory stays that of kMaxFilms images.
constexpr int kMaxFilms = 16;
}  // namespace

int ChainSweeper::thread_count(const RenderSettings& settings) {
  return settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
}

ChainSweeper::ChainSweeper(const RenderSettings& settings, ProgressReporter& progress,
                           ChainFrame& run, uint64_t pixels, int blocks,
                           std::vector<std::string> names, size_t layers)
    : settings_(settings),
      progress_(progress),
      run_(run),
      pixels_(pixels),
      threads_(thread_count(settings)),
      arena_(std::make_unique<tbb::task_arena>(threads_)),
      blocks_(blocks),
      owned_(cluster::share(uint64_t(blocks))),
      names_(std::move(names)),
      stats_(size_t(blocks), std::vector<BlockCounter>(names_.size())),
      films_(std::min(size_t(threads_), std::max<size_t>(1, size_t(kMaxFilms) / layers)),
             FixedPointFilm(pixels * layers)),
      shared_films_(size_t(threads_) > films_.size()),
      timed_(settings.time_limit_s > 0.0) {}

ChainSweeper::~ChainSweeper() = default;

std::vector<int64_t> ChainSweeper::film_units() const {
  std::vector<int64_t> units;
  if (!FixedPointFilm::total_units(films_, units))
    throw Error("the MCMC film overflowed: too many mutations' worth of weight in one pixel");
  return units;
}

void ChainSweeper::load_film_units(const std::vector<int64_t>& units) {
  FixedPointFilm::load_units(films_, units);
}

void ChainSweeper::save_stats(StateWriter& out) const {
  for (const std::vector<BlockCounter>& block : stats_)
    for (const StrategyStats& counter : block) out.put<StrategyStats>(counter);
}

void ChainSweeper::load_stats(StateReader& in) {
  for (std::vector<BlockCounter>& block : stats_)
    for (StrategyStats& counter : block) counter = in.get<StrategyStats>();
}

std::vector<StrategyStats> ChainSweeper::merged_stats() const {
  std::vector<uint64_t> counts;
  std::vector<double> sums;
  for (const std::vector<BlockCounter>& block : stats_)
    for (const StrategyStats& st : block) {
      counts.insert(counts.end(),
                    {st.proposed, st.not_applicable, st.failed, st.accepted, st.fallbacks});
      sums.push_back(st.acceptance_sum);
    }
  cluster::sum_to_root(counts);
  cluster::sum_to_root(sums);
  std::vector<StrategyStats> out(names_.size());
  for (size_t b = 0, k = 0; b < stats_.size(); ++b)
    for (size_t i = 0; i < names_.size(); ++i, ++k) {
      StrategyStats st;
      st.proposed = counts[5 * k], st.not_applicable = counts[5 * k + 1];
      st.failed = counts[5 * k + 2], st.accepted = counts[5 * k + 3];
      st.fallbacks = counts[5 * k + 4], st.acceptance_sum = sums[k];
      out[i].merge(st);
    }
  return out;
}

void ChainSweeper::root_decides(uint64_t& value) const {
  if (cluster::size() == 1 || !timed_) return;
  StateWriter out;
  out.put(value);
  std::string data = out.take();
  cluster::broadcast(data);
  value = StateReader(data).get<uint64_t>();
}

void ChainSweeper::snapshot(ChainSteps& chains, uint64_t done) {
  snapshot_image(done, chains.compose(done));
}

void ChainSweeper::snapshot_image(uint64_t done, const Image& image) {
  const auto begin = std::chrono::steady_clock::now();
  const std::vector<StrategyStats> merged = merged_stats();
  std::vector<StrategyAcceptance> acceptance;
  for (size_t i = 0; i < names_.size(); ++i)
    acceptance.push_back({names_[i], merged[i].mean_acceptance()});
  settings_.snapshots->snapshot(double(done) / double(pixels_), run_.counted_seconds(), image,
                                acceptance);
  run_.write_off(std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
}

// How much of the direct light's budget is to be done by the end of the sweep under way: the
// share of the chains' budget it ends at, or under a time budget alone the share of the time
// spent (rank 0's clock: the direct pass runs the same samples on every rank).
double ChainSweeper::direct_share(const ChainSteps& chains) const {
  if (chains.planned() != UINT64_MAX)
    return std::min(1.0, double(chains.sweep_end()) / double(chains.planned()));
  uint64_t share = std::bit_cast<uint64_t>(run_.counted_seconds() / settings_.time_limit_s);
  root_decides(share);
  return std::min(1.0, std::bit_cast<double>(share));
}

RenderResult ChainSweeper::run(ChainSteps& chains, const std::string& label) {
  const auto save = [&](StateWriter& out) {
    run_.save(out, [&](StateWriter& section) { chains.save(section); });
  };
  const auto pause = [&] { RenderControl::pause(run_.control(), save); };
  progress_.start(label, timed_ ? 0 : chains.planned(), settings_.time_limit_s);
  progress_.advance(chains.taken_before());
  bool stopped = false, stopped_in_direct = false;
  while (true) {
    if (!chains.in_sweep()) {
      if (chains.spent()) break;
      uint64_t time_up =
          timed_ && chains.may_end_for_time() && run_.counted_seconds() >= settings_.time_limit_s;
      root_decides(time_up);
      if (time_up) break;
      chains.begin_sweep(chains.rounds());
    } else {
      chains.continue_sweep();
    }
    // The direct light first takes its share of the work up to the sweep's end.
    if (!run_.direct_up_to(direct_share(chains), pause)) {
      stopped = stopped_in_direct = true;
      break;
    }
    if (!chains.keep_pace(chains.sweep_end())) {
      stopped = true;
      break;
    }
    const double sweep_start = run_.elapsed();
    const double steps_start = profile_.enabled ? SweepProfile::now() : 0.0,
                 steps_cpu_start = profile_.enabled ? SweepProfile::thread_cpu() : 0.0;
    arena_->execute([&] {
      tbb::parallel_for(0, blocks_, [&](int block) {
        if (!owns_block(uint64_t(block))) return;
        const size_t film =
            size_t(std::max(tbb::this_task_arena::current_thread_index(), 0)) % films_.size();
        // Progress once per block: a shared counter per chain would bounce between cores
        // (EMLT's chains take one step at a time).
        progress_.advance(chains.sweep_block(block, film));
      });
    });
    if (profile_.enabled) {
      profile_.steps += SweepProfile::now() - steps_start;
      profile_.steps_cpu += SweepProfile::thread_cpu() - steps_cpu_start;
    }
    // A pause on any rank pauses all of them, at the same point of the loop (interruption.h).
    const bool behind = chains.behind();
    std::vector<uint64_t> lengths = chains.exchange_lengths();
    const double agreement_start = profile_.enabled ? SweepProfile::now() : 0.0;
    const interruption::Decision decision = interruption::agree(behind, lengths);
    if (profile_.enabled) profile_.agreement += SweepProfile::now() - agreement_start;
    if (!decision.incomplete) {
      // A timed render checks its budget between sweeps: they grow while they are short.
      uint64_t rounds = chains.rounds();
      if (timed_ && chains.rounds_grow() &&
          run_.elapsed() - sweep_start < std::min(0.05, settings_.time_limit_s / 50.0))
        rounds *= 2;
      root_decides(rounds);
      chains.rounds() = rounds;
    }
    chains.sweep_agreed(decision.incomplete, lengths);
    if (decision.pause()) {
      pause();
      if (decision.stop && (decision.incomplete || !chains.spent())) {
        stopped = true;
        break;
      }
    }
  }
  // The direct light's whole budget, when the chains' is done (under a time budget, its
  // share of the time).
  if (!stopped && !run_.direct_up_to(1.0, pause)) stopped = true;
  profile_.print();
  progress_.finish();

  const uint64_t done = chains.final_done();
  RenderResult result;
  result.image = chains.compose(done);
  // A stopped render's log ends with the image it writes, as a finished one's does.
  if (settings_.snapshots && chains.log_final(done)) snapshot_image(done, result.image);
  if (!stopped) RenderControl::finish(run_.control(), save);
  result.interrupted = stopped;
  // Stopped before any chain took a step: the image is the direct light so far, and says so.
  if (stopped_in_direct && done == 0) result.stopped_in = "the direct-light pass";
  result.seconds = run_.counted_seconds();
  result.samples = done;
  result.samples_per_pixel = int(std::llround(double(done) / double(pixels_)));
  result.per_pixel = double(done) / double(pixels_);
  return result;
}

}  // namespace emlt
