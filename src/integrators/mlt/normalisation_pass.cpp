#include "emlt/integrators/mlt/normalisation_pass.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <span>
#include <vector>

#include "emlt/core/cluster.h"
#include "emlt/core/interruption.h"

namespace emlt {

NormalisationPass::NormalisationPass(const Scene& scene, const BootstrapParams& params, double rate)
    : scene_(scene), params_(params), rate_(rate) {}

void NormalisationPass::split_by_length(std::vector<bool> counted) {
  counted_ = std::move(counted);
  lengths_.assign(counted_.size(), NormalisationSums{});
}

void NormalisationPass::start(const Bootstrap& bootstrap) {
  first_sample_ = bootstrap.samples;
  if (!split()) {
    sums_ = {bootstrap.samples, bootstrap.sum, bootstrap.sum_squares, bootstrap.largest_sample};
    return;
  }
  // The pool's candidates sit in sample order, each sample's in the order of its strategies,
  // as bootstrap_sample_lengths sums them; samples without candidates count as zeros.
  sums_ = {};
  lengths_.assign(counted_.size(), NormalisationSums{});
  std::vector<double> by_length(counted_.size(), 0.0);
  const auto flush = [&] {
    double total = 0.0;
    for (size_t k = 0; k < by_length.size(); ++k) {
      if (by_length[k] > 0.0) lengths_[k].add(by_length[k]);
      if (counted_[k]) total += by_length[k];
      by_length[k] = 0.0;
    }
    if (total > 0.0) sums_.add(total);
  };
  for (size_t i = 0; i < bootstrap.candidates.size(); ++i) {
    const BootstrapCandidate& c = bootstrap.candidates[i];
    if (i > 0 && c.sample != bootstrap.candidates[i - 1].sample) flush();
    const int k = int(c.s) + int(c.t) - 1 - params_.min_edges;
    if (k >= 0 && k < int(by_length.size())) by_length[size_t(k)] += c.weight;
  }
  flush();
  sums_.samples = bootstrap.samples;
  for (NormalisationSums& l : lengths_) l.samples = bootstrap.samples;
}

void NormalisationPass::start(uint64_t samples, double b, double standard_error) {
  const double n = double(samples);
  first_sample_ = samples;
  sums_ = {samples, b * n, n * (standard_error * standard_error * n + b * b), 0.0};
}

uint64_t NormalisationPass::due(uint64_t mutations) const {
  if (!(rate_ > 0.0)) return 0;
  // Sample numbers are 32-bit (a stream each): the pass stops short of the last group.
  const uint64_t room =
      (uint64_t(UINT32_MAX) - std::min<uint64_t>(first_sample_, UINT32_MAX)) / kGroup * kGroup;
  const double wanted = std::ceil(rate_ * double(mutations) / double(kGroup)) * double(kGroup);
  return wanted >= double(room) ? room : uint64_t(wanted);
}

bool NormalisationPass::up_to(uint64_t mutations) {
  const uint64_t target = due(mutations), drawn_before = drawn();
  if (target <= drawn_before) return true;
  const auto begin = std::chrono::steady_clock::now();
  // Groups [first_group, last_group) of kGroup samples from the bootstrap's end.
  const uint64_t first_group = drawn_before / kGroup, last_group = target / kGroup;
  const uint64_t groups = last_group - first_group;
  struct alignas(64) Group {
    NormalisationSums total;
    std::vector<NormalisationSums> lengths;
  };
  std::vector<Group> results(groups);
  std::atomic<bool> interrupted{false};
  const std::pair<uint64_t, uint64_t> owned = cluster::share(groups);
  const uint64_t mine_first = owned.first, mine_last = owned.second;
  const int threads =
      params_.threads > 0 ? params_.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena(threads).execute([&] {
    tbb::parallel_for(mine_first, mine_last, [&](uint64_t g) {
      Group& out = results[g];
      const uint32_t first = uint32_t(first_sample_ + (first_group + g) * kGroup);
      // A group at a time between stop checks: a group takes milliseconds.
      if (interrupted || interruption::stop_requested()) {
        interrupted = true;
        return;
      }
      if (!split()) {
        bootstrap_sample_totals(scene_, params_, first, first + uint32_t(kGroup),
                                [&](double x) { out.total.add(x); });
        return;
      }
      out.lengths.assign(counted_.size(), NormalisationSums{});
      bootstrap_sample_lengths(scene_, params_, first, first + uint32_t(kGroup),
                               [&](std::span<const double> by_length) {
                                 double total = 0.0;
                                 for (size_t k = 0; k < by_length.size(); ++k) {
                                   out.lengths[k].add(by_length[k]);
                                   if (counted_[k]) total += by_length[k];
                                 }
                                 out.total.add(total);
                               });
    });
  });
  bool any_interrupted = interrupted.load();
  if (cluster::size() > 1) {
    StateWriter mine;
    mine.put<uint8_t>(any_interrupted);
    for (uint64_t g = mine_first; g < mine_last; ++g) {
      mine.put(results[g].total);
      if (split()) mine.put_vector(results[g].lengths);
    }
    const std::vector<std::string_view> parts = cluster::gather_everywhere(mine.data());
    for (int r = 0; r < int(parts.size()); ++r) {
      StateReader in(parts[size_t(r)]);
      any_interrupted |= in.get<uint8_t>() != 0;
      const auto [first, last] = cluster::share(groups, r, int(parts.size()));
      for (uint64_t g = first; g < last; ++g) {
        results[g].total = in.get<NormalisationSums>();
        if (split()) results[g].lengths = in.get_vector<NormalisationSums>(counted_.size());
      }
    }
  }
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  if (any_interrupted) return false;
  for (const Group& group : results) {  // group order: the same sums at any thread count
    sums_.add(group.total);
    for (size_t k = 0; k < group.lengths.size(); ++k) lengths_[k].add(group.lengths[k]);
  }
  return true;
}

void NormalisationPass::save(StateWriter& out) const {
  out.put(first_sample_);
  out.put(sums_.samples);
  out.put(sums_.sum);
  out.put(sums_.sum_squares);
  out.put(sums_.largest);
  out.put(seconds_);
  if (split()) out.put_vector(lengths_);
}

void NormalisationPass::load(StateReader& in) {
  first_sample_ = in.get<uint64_t>();
  sums_.samples = in.get<uint64_t>();
  sums_.sum = in.get<double>();
  sums_.sum_squares = in.get<double>();
  sums_.largest = in.get<double>();
  seconds_ = in.get<double>();
  bool consistent = first_sample_ > 0 && sums_.samples >= first_sample_ &&
                    sums_.samples <= UINT32_MAX && (sums_.samples - first_sample_) % kGroup == 0 &&
                    std::isfinite(sums_.sum) && sums_.sum > 0.0 &&
                    std::isfinite(sums_.sum_squares) && std::isfinite(sums_.largest) &&
                    sums_.largest >= 0.0 && sums_.largest <= sums_.sum && std::isfinite(seconds_);
  if (split()) {
    lengths_ = in.get_vector<NormalisationSums>(counted_.size());
    for (const NormalisationSums& l : lengths_)
      consistent = consistent && l.consistent() && l.samples == sums_.samples;
  }
  if (!consistent) throw StateError("the saved normalisation's figures are inconsistent");
}

}  // namespace emlt
