#include "emlt/integrators/mlt/mlt_chains.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <span>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/film/filter_lobes.h"
#include "emlt/run/snapshot.h"
#include "emlt/scene/scene.h"

namespace emlt {

namespace {

// Up to 256 blocks (BlockOutput).
constexpr int kMaxBlocks = 256;

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

std::vector<std::string> strategy_names(const StrategyMix& mix) {
  std::vector<std::string> names;
  for (size_t i = 0; i < mix.size(); ++i) names.push_back(mix.name(i));
  return names;
}

}  // namespace

std::vector<MltChain> MltChains::load_chains(StateReader& in, const PathCodec& codec,
                                             MltStatistics& stats, uint64_t ensemble_chains) {
  stats.bootstrap_b = in.get<double>();
  stats.b_standard_error = in.get<double>();
  stats.bootstrap_samples = in.get<uint64_t>();
  stats.bootstrap_seconds = in.get<double>();
  const uint64_t saved_count = in.get<uint64_t>();
  if (saved_count == 0 || saved_count > (uint64_t(1) << 20) ||
      (ensemble_chains > 0 && saved_count != ensemble_chains))
    throw StateError("the saved chains do not fit this render (" + std::to_string(saved_count) +
                     " chains)");
  std::vector<MltChain> chains(saved_count);
  for (MltChain& chain : chains) chain.load(codec, in);
  return chains;
}

MltChains::MltChains(MltSetup setup, std::vector<MltChain> chains, McmcRun& run,
                     ProgressReporter& progress, MltStatistics& stats, StateReader* resumed_section)
    : setup_(std::move(setup)),
      chains_(std::move(chains)),
      stats_(stats),
      codec_(setup_.scene),
      width_(setup_.scene.camera().width()),
      height_(setup_.scene.camera().height()),
      pixels_(uint64_t(width_) * uint64_t(height_)),
      chain_count_(chains_.size()),
      timed_(setup_.settings.time_limit_s > 0.0),
      record_moves_(!setup_.settings.aniso_map_path.empty()),
      sweeper_(setup_.settings, progress, run, pixels_,
               int(std::min<uint64_t>(setup_.ensemble ? setup_.ensemble->size() : chain_count_,
                                      kMaxBlocks)),
               strategy_names(setup_.mix)),
      move_films_(record_moves_ ? sweeper_.films().size() : 0, FixedPointFilm(pixels_, 256.0)),
      round_size_(std::max<uint64_t>(pixels_, chain_count_)),
      run_(run),
      resumed_(resumed_section != nullptr) {
  for (int b = 0; b < sweeper_.blocks(); ++b)
    blocks_.push_back({sweeper_.block_stats(size_t(b)), {}});
  // Under MPI each rank runs a contiguous share of the blocks (of each half, in EMLT); a
  // chain is in one block, so it is moved by one rank only. A sweep's chains fall in its
  // blocks as chain j of `count` in block b when count b / B <= j < count (b + 1) / B (B
  // blocks, sweep_block()), so a rank's blocks hold one range of them.
  const uint64_t sweep_chains = setup_.ensemble ? setup_.ensemble->size() : chain_count_;
  first_owned_chain_ = sweep_chains * sweeper_.owned_blocks().first / blocks_.size();
  end_owned_chain_ = sweep_chains * sweeper_.owned_blocks().second / blocks_.size();
  if (setup_.ensemble) {
    setup_.ctx.ensemble = &setup_.ensemble->guides();
    setup_.ensemble->attach(blocks_.size(), sweeper_.profile());
  }
  if (resumed_) load(*resumed_section);
}

// Which rank moves a chain (every chain belongs to one block of its sweep).
bool MltChains::owns_chain(uint64_t c) const {
  const uint64_t size = setup_.ensemble ? setup_.ensemble->size() : 0;
  const uint64_t j = setup_.ensemble && c >= size ? c - size : c;
  return j >= first_owned_chain_ && j < end_owned_chain_;
}

void MltChains::save(StateWriter& out) const {
  out.put<double>(stats_.bootstrap_b);
  out.put<double>(stats_.b_standard_error);
  out.put<uint64_t>(stats_.bootstrap_samples);
  out.put<double>(stats_.bootstrap_seconds);
  out.put<uint64_t>(chains_.size());
  const bool guide_copies = setup_.ensemble && setup_.ensemble->guide_copies();
  for (size_t c = 0; c < chains_.size(); ++c)
    chains_[c].save(codec_, out, guide_copies && !owns_chain(c));
  sweeper_.save_stats(out);
  out.put_vector(sweeper_.film_units());
  std::vector<int64_t> units;
  if (record_moves_ && !FixedPointFilm::total_units(move_films_, units))
    throw Error("the --aniso-map tallies overflowed: too many proposals per pixel");
  out.put_vector(units);
  out.put(sweep_.active);
  out.put(sweep_.first);
  out.put(sweep_.count);
  out.put(sweep_.size);
  out.put(sweep_.done_before);
  out.put(done_);
  out.put(next_checkpoint_);
  const EnsembleSchedule* ensemble = setup_.ensemble.get();
  out.put(ensemble ? ensemble->half : uint64_t(0));
  out.put(timed_rounds_);
  out.put(ensemble ? ensemble->alpha_sum : 0.0);
  AlphaTally alpha;
  for (const BlockOutput& block : blocks_) alpha.merge(block.alpha);
  out.put(alpha);
  out.put(ensemble ? ensemble->swaps : uint64_t(0));
  out.put(ensemble ? ensemble->tree_seconds : 0.0);
  setup_.normalisation.save(out);
}

void MltChains::load(StateReader& in) {
  sweeper_.load_stats(in);
  const std::vector<int64_t> units = in.get_vector<int64_t>(3 * pixels_);
  sweeper_.load_film_units(units);
  const std::vector<int64_t> move_units = in.get_vector<int64_t>(record_moves_ ? 3 * pixels_ : 0);
  if (record_moves_) FixedPointFilm::load_units(move_films_, move_units);
  sweep_.active = in.get<uint8_t>();
  sweep_.first = in.get<uint64_t>();
  sweep_.count = in.get<uint64_t>();
  sweep_.size = in.get<uint64_t>();
  sweep_.done_before = in.get<uint64_t>();
  done_ = in.get<uint64_t>();
  next_checkpoint_ = in.get<uint64_t>();
  const uint64_t half = in.get<uint64_t>();
  timed_rounds_ = in.get<uint64_t>();
  const double alpha_sum = in.get<double>();
  // The merged α tally is kept by the first block.
  blocks_.front().alpha = in.get<AlphaTally>();
  const uint64_t swaps = in.get<uint64_t>();
  const double tree_seconds = in.get<double>();
  // A checkpoint of format 4 ends here: its normalisation starts from the bootstrap's figures.
  if (in.remaining() > 0)
    setup_.normalisation.load(in);
  else
    setup_.normalisation.start(stats_.bootstrap_samples, stats_.bootstrap_b,
                               stats_.b_standard_error);
  in.expect_end();
  EnsembleSchedule* ensemble = setup_.ensemble.get();
  if (ensemble) {
    ensemble->half = half;
    ensemble->alpha_sum = alpha_sum;
    ensemble->swaps = swaps;
    ensemble->tree_seconds = tree_seconds;
  }
  // Every count that steers the loop is checked, so that a damaged state can neither
  // loop forever nor index past the chains.
  const uint64_t ensemble_size = ensemble ? ensemble->size() : 0;
  uint64_t left = 0;
  bool consistent = half <= 1 && (ensemble || half == 0) && is_checkpoint(next_checkpoint_) &&
                    next_checkpoint_ <= (1ull << 40) && is_checkpoint(timed_rounds_) &&
                    timed_rounds_ <= (1ull << 40) && std::isfinite(stats_.bootstrap_b) &&
                    stats_.bootstrap_b > 0.0 &&
                    setup_.normalisation.bootstrap_samples() == stats_.bootstrap_samples &&
                    std::isfinite(alpha_sum);
  // A filter's negative lobes may leave a pixel's sum below zero.
  const bool signed_sums = has_negative_lobes(setup_.scene.description().camera.filter);
  for (const int64_t u : units) consistent &= u >= 0 || signed_sums;
  if (consistent && sweep_.active) {
    // A sweep is all the chains (MLT) or one half (EMLT).
    consistent = ensemble ? sweep_.first == half * ensemble_size && sweep_.count == ensemble_size
                          : sweep_.first == 0 && sweep_.count == chain_count_;
    // The chains take every step a state promises them, so the sweep is held to what the
    // loop gives one: it never crosses a checkpoint, and takes `it` steps per path in EMLT,
    // at most its rounds in a timed MLT render.
    uint64_t most = 0, rounds = 0;
    if (__builtin_mul_overflow(next_checkpoint_, pixels_, &most)) most = UINT64_MAX;
    most -= std::min(most, sweep_.done_before);
    if (ensemble)
      most = std::min(most, ensemble_size * ensemble->iterations());
    else if (timed_ && !__builtin_mul_overflow(timed_rounds_, round_size_, &rounds))
      most = std::min(most, rounds);
    consistent = consistent && sweep_.size <= most;
  }
  for (uint64_t c = 0; consistent && c < chain_count_; ++c) {
    const uint64_t chain_left = chains_[size_t(c)].sweep_left;
    const bool in_sweep = sweep_.active && c >= sweep_.first && c < sweep_.first + sweep_.count;
    consistent = in_sweep ? chain_left <= sweep_.size : chain_left == 0;
    left += chain_left;
  }
  // (Under MPI a rank holds only its own chains' steps left, and `done` counts every rank's.)
  if (consistent && sweep_.active)
    consistent = left <= sweep_.size && done_ <= sweep_.done_before + sweep_.size &&
                 done_ >= sweep_.done_before;
  if (!consistent) throw StateError("the saved chains' schedule is inconsistent");
  // A sweep under way is finished before anything else (and cannot be cut short).
  const uint64_t committed = sweep_.active ? sweep_.done_before + sweep_.size : done_;
  if (!timed_ && committed > setup_.planned)
    throw StateError("the checkpoint has " + std::to_string(committed / pixels_) +
                     " mutations per pixel done or under way, more than this run's budget of " +
                     std::to_string(setup_.planned / pixels_) +
                     " (a resumed render may extend the budget, not cut it)");
}

// Sweeps: for MLT, every chain takes its share of the steps up to the next checkpoint (a
// power of two in mutations per pixel) in one visit, so that its path stays in cache
// (one round of a mutation per pixel at a time ran 10 % slower with 16384 chains); a
// timed render starts with one round and doubles the sweep while sweeps are short, since
// the time budget is checked between sweeps. For EMLT, half-sweeps of `it` steps for
// each path of X. No sweep crosses a checkpoint, so snapshots fall on them exactly. A
// pause (a checkpoint falling due, a stop) cuts a sweep short with every chain's steps
// left recorded; the sweep then goes on from there, in this process or a resumed one.
void MltChains::begin_sweep(uint64_t rounds) {
  EnsembleSchedule* ensemble = setup_.ensemble.get();
  const uint64_t planned = setup_.planned;
  sweep_.first = 0;
  sweep_.count = chain_count_;
  sweep_.size = timed_ ? rounds * round_size_ : planned - done_;
  if (ensemble) {
    sweep_.first = ensemble->half * ensemble->size();
    sweep_.count = ensemble->size();
    sweep_.size = ensemble->size() * ensemble->iterations();
    ensemble->begin_half_sweep(chains_, sweeper_.arena());
  }
  sweep_.size = std::min(sweep_.size, planned - done_);
  if (done_ < next_checkpoint_ * pixels_)
    sweep_.size = std::min(sweep_.size, next_checkpoint_ * pixels_ - done_);
  for (uint64_t j = 0; j < sweep_.count; ++j) {
    MltChain& chain = chains_[size_t(sweep_.first + j)];
    chain.sweep_left = !(chain.target > 0.0) || !owns_chain(sweep_.first + j)
                           ? 0
                           : sweep_.size / sweep_.count + (j < sweep_.size % sweep_.count ? 1 : 0);
  }
  sweep_.done_before = done_;
  sweep_.active = 1;
}

void MltChains::continue_sweep() {
  if (setup_.ensemble) setup_.ensemble->continue_half_sweep(chains_, sweeper_.arena());
}

uint64_t MltChains::sweep_block(int block, size_t film_index) {
  const uint64_t first = sweep_.first, count = sweep_.count;
  const uint64_t begin = count * uint64_t(block) / blocks_.size();
  const uint64_t end = count * uint64_t(block + 1) / blocks_.size();
  const FilmSlot film{sweeper_.films()[film_index],
                      record_moves_ ? &move_films_[film_index] : nullptr, sweeper_.films_shared(),
                      setup_.scene.camera().filter()};
  EnsembleSchedule* exchange =
      setup_.ensemble && setup_.ensemble->guide_copies() ? setup_.ensemble.get() : nullptr;
  uint64_t block_steps = 0;
  for (uint64_t j = begin; j < end; ++j) {
    MltChain& chain = chains_[size_t(first + j)];
    if (j + 1 < end) prefetch_path(chains_[size_t(first + j + 1)].current);
    if (chain.sweep_left == 0) continue;
    if (interruption::requested()) break;
    const uint64_t steps = run_chain(chain, first + j, setup_.mix, setup_.ctx, setup_.rules,
                                     blocks_[size_t(block)], film, width_, height_);
    if (exchange && chain.moved) exchange->pack_moved(chains_, first + j, size_t(block));
    interruption::poll(steps);
    block_steps += steps;
  }
  return block_steps;
}

uint64_t MltChains::steps_left() const {
  uint64_t left = 0;
  for (uint64_t j = 0; j < sweep_.count; ++j) left += chains_[size_t(sweep_.first + j)].sweep_left;
  return left;
}

// EMLT under MPI: the lengths of the moved paths to exchange are agreed on with the rest.
std::vector<uint64_t> MltChains::exchange_lengths() {
  if (!setup_.ensemble || !setup_.ensemble->guide_copies()) return {};
  return setup_.ensemble->prepare_moved_paths();
}

void MltChains::sweep_agreed(bool incomplete, std::span<const uint64_t> lengths) {
  // (A complete sweep has no steps left on any rank: no sum to take.)
  std::vector<uint64_t> left = {steps_left()};
  if (incomplete) cluster::sum_everywhere(left);
  done_ = sweep_.done_before + sweep_.size - left[0];
  if (incomplete) return;
  sweep_.active = 0;
  if (EnsembleSchedule* ensemble = setup_.ensemble.get()) {
    if (ensemble->guide_copies()) ensemble->share_moved_paths(chains_, lengths);
    ensemble->swap();
  }
  for (; done_ >= next_checkpoint_ * pixels_; next_checkpoint_ *= 2)
    if (setup_.settings.snapshots && done_ == next_checkpoint_ * pixels_)
      sweeper_.snapshot(*this, done_);
}

bool MltChains::log_final(uint64_t done) {
  return !(done % pixels_ == 0 && is_checkpoint(done / pixels_));
}

// The image after `mutations` steps: the direct part, plus the films' sum and each chain's
// weight not yet splatted (added to a copy: the chains go on untouched), scaled so the
// image's mean luminance is b. Complete on rank 0 (the films and the chains' unsplatted
// weights summed over ranks). It runs while the chains and films are held, at the render's
// peak memory: each buffer is released as soon as it is used.
Image MltChains::compose(uint64_t mutations_done) {
  const std::vector<FixedPointFilm>& films = sweeper_.films();
  std::vector<DVec3> total(pixels_, DVec3(0.0));
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
    for (uint64_t p = 0; p < pixels_; ++p)
      if (!FixedPointFilm::total(films, p, total[p])) throw overflowed();
  } else {
    std::vector<int64_t> units;
    if (!FixedPointFilm::total_units(films, units)) throw overflowed();
    cluster::sum_to_root(units);
    for (uint64_t p = 0; p < pixels_; ++p)
      total[p] = DVec3(double(units[3 * p]), double(units[3 * p + 1]), double(units[3 * p + 2])) /
                 FixedPointFilm::kUnitsPerValue;
  }
  {
    std::vector<double> carried(kCarriedFields * chains_.size(), 0.0);
    for (size_t c = 0; c < chains_.size(); ++c)
      if (owns_chain(c))
        put_carried(carried, c,
                    chains_[c].current.vertices.empty() ? Vec2(0.0f) : chains_[c].current.raster(),
                    chains_[c].contribution, chains_[c].target, chains_[c].carried);
    cluster::sum_to_root(carried);
    for (size_t c = 0; c < chains_.size(); ++c) {
      const double* f = &carried[kCarriedFields * c];
      splat(total, width_, height_, setup_.scene.camera().filter(), Vec2(float(f[0]), float(f[1])),
            DVec3(f[2], f[3], f[4]), f[5], f[6]);
    }
  }
  const double splatted = double(mutations_done) * double(live_) / double(chain_count_);
  const double b = setup_.normalisation.sums().b();
  const double scale = splatted > 0.0 ? double(pixels_) * b / splatted : 0.0;
  Image image = run_.direct_image();
  for (uint64_t p = 0; p < pixels_; ++p) image.pixels[p] += Rgb(total[p] * scale);
  return image;
}

RenderResult MltChains::render(const std::string& name) {
  EnsembleSchedule* ensemble = setup_.ensemble.get();
  if (resumed_ && ensemble && ensemble->guide_copies())
    ensemble->resend_own(chains_, [this](uint64_t c) { return owns_chain(c); });
  for (const MltChain& chain : chains_) live_ += chain.target > 0.0;
  RenderResult result = sweeper_.run(*this, name);
  finish_statistics();
  return result;
}

void MltChains::finish_statistics() {
  const NormalisationSums& sums = setup_.normalisation.sums();
  stats_.b = sums.b();
  stats_.b_standard_error = sums.error();
  stats_.b_samples = sums.samples;
  stats_.b_largest_share = sums.largest_share();
  stats_.normalisation_seconds = setup_.normalisation.seconds();
  if (record_moves_) {
    std::vector<int64_t> units;
    if (!FixedPointFilm::total_units(move_films_, units))
      throw Error("the --aniso-map tallies overflowed: too many proposals per pixel");
    cluster::sum_to_root(units);
    if (cluster::is_root()) {
      std::vector<FixedPointFilm> merged(1, FixedPointFilm(pixels_, 256.0));
      FixedPointFilm::load_units(merged, units);
      write_move_map(setup_.settings.aniso_map_path, merged, width_, height_);
    }
  }
  {
    // α's tally over the blocks and ranks: counts and sum add up; the extremes of positive
    // doubles order as their bit patterns, so a maximum over ranks gives both.
    AlphaTally alpha;
    for (const BlockOutput& block : blocks_) alpha.merge(block.alpha);
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
  stats_.strategies = sweeper_.merged_stats();
  stats_.chains = chain_count_;
  stats_.mutations = done_;
  if (const EnsembleSchedule* ensemble = setup_.ensemble.get()) {
    stats_.swaps = ensemble->swaps;
    stats_.tree_seconds = ensemble->tree_seconds;
    stats_.ensemble_size = ensemble->size();
    stats_.ensemble_neighbours = uint64_t(ensemble->params().neighbours);
    stats_.ensemble_iterations = ensemble->iterations();
    stats_.mean_alpha = stats_.swaps ? ensemble->alpha_sum / double(stats_.swaps) : 0.0;
    if (stats_.alpha.total() > 0) stats_.mean_alpha = stats_.alpha.mean();
  }
}

}  // namespace emlt
