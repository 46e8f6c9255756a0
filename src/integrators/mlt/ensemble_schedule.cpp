#include "emlt/integrators/mlt/ensemble_schedule.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/integrators/mlt/mlt_step.h"
#include "emlt/scene/scene.h"

namespace emlt {

EnsembleSchedule::EnsembleSchedule(const Scene& scene, const RenderSettings& settings,
                                   EnsembleParams base, uint64_t pixels)
    : size_(settings.ensemble_size > 0 ? uint64_t(settings.ensemble_size)
                                       : std::clamp<uint64_t>(pixels / 2, 1, 16384)),
      iterations_(settings.ensemble_iterations > 0 ? uint64_t(settings.ensemble_iterations)
                                                   : std::max<uint64_t>(1, pixels / (2 * size_))),
      params_(std::move(base)),
      frozen_(size_),
      width_(scene.camera().width()),
      height_(scene.camera().height()),
      seed_(settings.seed),
      guide_copies_(cluster::size() > 1) {
  if (settings.ensemble_neighbours > 0) params_.neighbours = settings.ensemble_neighbours;
  if (settings.ensemble_similarity_length > 0.0)
    params_.similarity_length = settings.ensemble_similarity_length;
  if (!(params_.similarity_length > 0.0))
    params_.similarity_length = double(scene.bounds_radius()) / std::sqrt(3.0);
  params_.plane_fallback = settings.ensemble_plane_fallback;
  if (settings.ensemble_aniso_weighted) params_.aniso_printed_covariance = false;
  if (settings.ensemble_aniso_scale > 0.0)
    params_.aniso_covariance_scale = settings.ensemble_aniso_scale;
  params_.aniso_smallest_scale = settings.ensemble_aniso_smallest_scale;
  if (settings.ensemble_nearby_guides) params_.selection = GuideSelection::Nearby;
  if (settings.ensemble_alpha_from_ensemble) params_.alpha_source = AlphaSource::Ensemble;
  if (settings.ensemble_alpha > 0.0) {
    params_.adaptive_alpha = false;
    params_.alpha_fixed = settings.ensemble_alpha;
  }
}

void EnsembleSchedule::build_guides(const std::vector<MltChain>& chains, tbb::task_arena& arena) {
  const auto tree_start = std::chrono::steady_clock::now();
  const uint64_t other = (1 - half) * size_;
  for (uint64_t i = 0; i < size_; ++i) {
    const MltChain& y = chains[size_t(other + i)];
    frozen_[i] = y.target > 0.0 ? &y.current : nullptr;
  }
  arena.execute([&] { guides_.build(frozen_, width_, height_, seed_, params_); });
  tree_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - tree_start).count();
  guides_ready_ = true;
}

void EnsembleSchedule::begin_half_sweep(const std::vector<MltChain>& chains,
                                        tbb::task_arena& arena) {
  const double guides_start = profile_->enabled ? SweepProfile::now() : 0.0;
  build_guides(chains, arena);
  if (profile_->enabled) profile_->guides += SweepProfile::now() - guides_start;
  alpha_sum += guides_.alpha();
}

void EnsembleSchedule::continue_half_sweep(const std::vector<MltChain>& chains,
                                           tbb::task_arena& arena) {
  if (!guides_ready_) build_guides(chains, arena);
}

void EnsembleSchedule::swap() {
  half = 1 - half;
  ++swaps;
  guides_ready_ = false;
}

void EnsembleSchedule::attach(size_t blocks, SweepProfile& profile) {
  packed_.resize(guide_copies_ ? blocks : 0);
  profile_ = &profile;
}

void EnsembleSchedule::pack_moved(std::vector<MltChain>& chains, uint64_t c, size_t block) {
  MltChain& chain = chains[c];
  PackedPaths& out = packed_[block];
  chain.moved = false;
  out.ids.push_back(uint32_t(c));
  out.records.put(chain.target);
  PathCodec::pack_guide(chain.current, out.records);
}

// The chains' indices go first, so that the receiver can ask for the paths it will
// overwrite ahead of time (they lie scattered in memory). The blocks keep theirs until they
// are sent: a sweep cut short goes on packing.
std::vector<uint64_t> EnsembleSchedule::prepare_moved_paths() {
  const double t0 = profile_->enabled ? SweepProfile::now() : 0.0;
  all_ids_.clear();
  for (const PackedPaths& block : packed_)
    all_ids_.insert(all_ids_.end(), block.ids.begin(), block.ids.end());
  StateWriter& mine = exchange_;
  mine.clear();
  mine.put_vector(all_ids_);
  mine.put<uint64_t>(packed_.size());
  for (const PackedPaths& block : packed_) mine.put_block(block.records.data());
  std::vector<uint64_t> lengths(size_t(cluster::size()), 0);
  lengths[size_t(cluster::rank())] = mine.data().size();
  if (profile_->enabled) profile_->pack += SweepProfile::now() - t0;
  return lengths;
}

void EnsembleSchedule::share_moved_paths(std::vector<MltChain>& chains,
                                         std::span<const uint64_t> lengths) {
  const double t1 = profile_->enabled ? SweepProfile::now() : 0.0;
  for (PackedPaths& block : packed_) {
    block.ids.clear();
    block.records.clear();
  }
  profile_->bytes_sent += exchange_.data().size();
  const std::vector<std::string_view> parts = cluster::gather_everywhere(exchange_.data(), lengths);
  const double t2 = profile_->enabled ? SweepProfile::now() : 0.0;
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
          const MltChain& ahead = chains.at(ids[k + kAhead]);
          __builtin_prefetch(&ahead);
          prefetch_path(ahead.current);
        }
        MltChain& chain = chains.at(ids.at(k));
        chain.target = records.get<double>();
        PathCodec::unpack_guide(records, chain.current);
      }
    }
    if (k != ids.size()) throw StateError("the moved paths of a rank are damaged");
  }
  if (profile_->enabled) profile_->gather += t2 - t1, profile_->unpack += SweepProfile::now() - t2;
}

void EnsembleSchedule::resend_own(std::vector<MltChain>& chains,
                                  const std::function<bool(uint64_t)>& owns_chain) {
  for (uint64_t c = 0; c < chains.size(); ++c)
    if (owns_chain(c)) pack_moved(chains, c, 0);
  std::vector<uint64_t> lengths = prepare_moved_paths();
  cluster::max_everywhere(lengths);
  share_moved_paths(chains, lengths);
}

}  // namespace emlt
