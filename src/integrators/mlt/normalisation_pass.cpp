#include "emlt/integrators/mlt/normalisation_pass.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#include "emlt/core/cluster.h"
#include "emlt/core/interruption.h"

namespace emlt {

NormalisationPass::NormalisationPass(const Scene& scene, const BootstrapParams& params, double rate)
    : scene_(scene), params_(params), rate_(rate) {}

void NormalisationPass::start(const Bootstrap& bootstrap) {
  first_sample_ = bootstrap.samples;
  sums_ = {bootstrap.samples, bootstrap.sum, bootstrap.sum_squares, bootstrap.largest_sample};
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
    double sum = 0.0, sum_squares = 0.0, largest = 0.0;
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
      const uint64_t first = first_sample_ + (first_group + g) * kGroup;
      // A group at a time between stop checks: a group takes milliseconds.
      if (interrupted || interruption::stop_requested()) {
        interrupted = true;
        return;
      }
      bootstrap_sample_totals(scene_, params_, uint32_t(first), uint32_t(first + kGroup),
                              [&](double x) {
                                out.sum += x;
                                out.sum_squares += x * x;
                                out.largest = std::max(out.largest, x);
                              });
    });
  });
  bool any_interrupted = interrupted.load();
  if (cluster::size() > 1) {
    StateWriter mine;
    mine.put<uint8_t>(any_interrupted);
    for (uint64_t g = mine_first; g < mine_last; ++g) mine.put(results[g]);
    const std::vector<std::string_view> parts = cluster::gather_everywhere(mine.data());
    for (int r = 0; r < int(parts.size()); ++r) {
      StateReader in(parts[size_t(r)]);
      any_interrupted |= in.get<uint8_t>() != 0;
      const auto [first, last] = cluster::share(groups, r, int(parts.size()));
      for (uint64_t g = first; g < last; ++g) results[g] = in.get<Group>();
    }
  }
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  if (any_interrupted) return false;
  for (const Group& group : results) {  // group order: the same sums at any thread count
    sums_.sum += group.sum;
    sums_.sum_squares += group.sum_squares;
    sums_.largest = std::max(sums_.largest, group.largest);
  }
  sums_.samples = first_sample_ + target;
  return true;
}

void NormalisationPass::save(StateWriter& out) const {
  out.put(first_sample_);
  out.put(sums_.samples);
  out.put(sums_.sum);
  out.put(sums_.sum_squares);
  out.put(sums_.largest);
  out.put(seconds_);
}

void NormalisationPass::load(StateReader& in) {
  first_sample_ = in.get<uint64_t>();
  sums_.samples = in.get<uint64_t>();
  sums_.sum = in.get<double>();
  sums_.sum_squares = in.get<double>();
  sums_.largest = in.get<double>();
  seconds_ = in.get<double>();
  const bool consistent =
      first_sample_ > 0 && sums_.samples >= first_sample_ && sums_.samples <= UINT32_MAX &&
      (sums_.samples - first_sample_) % kGroup == 0 && std::isfinite(sums_.sum) &&
      sums_.sum > 0.0 && std::isfinite(sums_.sum_squares) && std::isfinite(sums_.largest) &&
      sums_.largest >= 0.0 && sums_.largest <= sums_.sum && std::isfinite(seconds_);
  if (!consistent) throw StateError("the saved normalisation's figures are inconsistent");
}

}  // namespace emlt
