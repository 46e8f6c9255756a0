#include "emlt/integrators/pss/pss_chains.h"

#include <algorithm>
#include <cmath>

#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/film/filter_lobes.h"
#include "emlt/scene/scene.h"

namespace emlt {

namespace {

constexpr uint64_t kChainStream = 0xc5500ull << 40;
constexpr int kBlocks = 64;
constexpr size_t kLarge = 0, kSmall = 1;  // the step kinds' statistics

// Adds weight * F / (f* + p_L b) of every contribution, at its raster position in the film's
// layer that starts at pixel `layer_start`.
void splat(FixedPointFilm& film, size_t layer_start, bool shared, const PixelFilter& filter,
           int width, int height, const PssSample& sample, double weight, double denominator) {
  if (!(weight > 0.0) || !(denominator > 0.0)) return;
  const double w = weight / denominator;
  for (const PssSplat& s : sample.splats) {
    const DVec3 value = DVec3(s.value) * w;
    if (filter.is_box()) {
      const int x = std::clamp(int(s.raster.x), 0, width - 1),
                y = std::clamp(int(s.raster.y), 0, height - 1);
      film.add(layer_start + size_t(y) * size_t(width) + size_t(x), value, shared);
    } else {
      filter.splat(s.raster, [&](uint32_t pixel, float fw) {
        film.add(layer_start + pixel, value * double(fw), shared);
      });
    }
  }
}

// The films' layers: the independent part's, then one for each length with chains.
size_t film_layers(const PssBootstrap& bootstrap) {
  size_t layers = 1;
  for (const int32_t chains : bootstrap.chains_of_length) layers += chains > 0;
  return layers;
}

// Statistics, counted per block of chains: the step kinds, then the path lengths: for MMLT
// the chain's, for PSSMLT the proposal's (its longest contributing path; a proposal that
// carries no light counts under "no light"), so that every proposal counts once.
std::vector<std::string> statistic_names(int min_edges, int max_edges, bool multiplexed) {
  std::vector<std::string> names = {"large", "small"};
  for (int k = min_edges; k <= max_edges; ++k) names.push_back("length " + std::to_string(k));
  if (!multiplexed) names.push_back("no light");
  return names;
}

}  // namespace

void PssBootstrap::save(StateWriter& out, const MltStatistics& stats) const {
  out.put<double>(standard_error);
  out.put<uint64_t>(stats.bootstrap_samples);
  out.put<double>(stats.bootstrap_seconds);
  out.put<uint64_t>(uint64_t(chain_count));
  out.put_vector(b_length);
  out.put_vector(chains_of_length);
  out.put_vector(seeds);
}

void PssBootstrap::load(StateReader& in, int lengths, MltStatistics& stats) {
  standard_error = in.get<double>();
  stats.b_standard_error = standard_error;
  stats.bootstrap_samples = in.get<uint64_t>();
  stats.bootstrap_seconds = in.get<double>();
  const uint64_t saved_count = in.get<uint64_t>();
  if (saved_count == 0 || saved_count > (uint64_t(1) << 20))
    throw StateError("the saved chains do not fit this render (" + std::to_string(saved_count) +
                     " chains)");
  chain_count = int(saved_count);
  b_length = in.get_vector<double>(uint64_t(lengths));
  chains_of_length = in.get_vector<int32_t>(uint64_t(lengths));
  seeds = in.get_vector<NormalisationSums>(uint64_t(lengths));
  // A length has chains exactly when the bootstrap saw light in it, and then seeds that
  // carry light; the chains add up.
  int64_t given = 0;
  for (size_t k = 0; k < size_t(lengths); ++k) {
    if (!std::isfinite(b_length[k]) || b_length[k] < 0.0 || chains_of_length[k] < 0 ||
        (chains_of_length[k] > 0) != (b_length[k] > 0.0) || !seeds[k].consistent() ||
        (chains_of_length[k] > 0 && !(seeds[k].sum > 0.0)))
      throw StateError("the saved bootstrap is inconsistent");
    given += chains_of_length[k];
  }
  if (given != chain_count) throw StateError("the saved bootstrap is inconsistent");
}

double PssBootstrap::b() const {
  double b = 0.0;
  for (const double b_k : b_length) b += b_k;
  return b;
}

PssChains::PssChains(PssSetup setup, McmcRun& run, ProgressReporter& progress, MltStatistics& stats,
                     StateReader* resumed_section)
    : setup_(std::move(setup)),
      stats_(stats),
      width_(setup_.scene.camera().width()),
      height_(setup_.scene.camera().height()),
      pixels_(uint64_t(width_) * uint64_t(height_)),
      layers_(film_layers(setup_.bootstrap)),
      chain_count_(uint64_t(setup_.bootstrap.chain_count)),
      block_count_(std::min(setup_.bootstrap.chain_count, kBlocks)),
      p_large_(std::clamp(setup_.settings.large_step_probability, 0.0, 1.0)),
      chains_(chain_count_),
      sweeper_(setup_.settings, progress, run, pixels_, block_count_,
               statistic_names(setup_.min_edges, setup_.max_edges, setup_.options.multiplexed),
               layers_),
      run_(run) {
  const RenderSettings& settings = setup_.settings;
  const bool multiplexed = setup_.options.multiplexed;
  const PssBootstrap& bootstrap = setup_.bootstrap;
  const double b = bootstrap.b();
  {
    size_t c = 0, layer = 0;
    for (size_t k = 0; k < bootstrap.b_length.size(); ++k) {
      has_chains_.push_back(bootstrap.chains_of_length[k] > 0);
      layer += has_chains_.back();
      for (int j = 0; j < bootstrap.chains_of_length[k]; ++j, ++c) {
        PssChain& chain = chains_[c];
        chain.u = PrimarySampleVector(float(settings.pss_sigma));
        chain.length = multiplexed ? setup_.min_edges + int(k) : 0;
        chain.index = k;
        chain.layer = layer;
        chain.b = bootstrap.b_length[k];
        chain.scale = multiplexed ? (bootstrap.b_length[k] / b) * double(chain_count_) /
                                        bootstrap.chains_of_length[k]
                                  : 1.0;
        chain.rng = Rng::for_item(derive_stream_seed(settings.seed, kChainStream), c);
      }
    }
  }
  // Under MPI each rank runs a contiguous share of the blocks, so it holds one range of
  // chains (the others' chains stay unseeded).
  first_owned_ = first_chain_of(sweeper_.owned_blocks().first);
  end_owned_ = first_chain_of(sweeper_.owned_blocks().second);
  stats_.strategy_names =
      statistic_names(setup_.min_edges, setup_.max_edges, setup_.options.multiplexed);
  no_light_row_ = 2 + size_t(setup_.max_edges - setup_.min_edges + 1);
  const bool timed = sweeper_.timed();
  const uint64_t budget =
      uint64_t(std::llround(std::max(settings.mutations_per_pixel, 0.0) * double(pixels_)));
  planned_steps_ = timed && !(settings.mutations_per_pixel > 0)
                       ? UINT64_MAX
                       : (budget + chain_count_ - 1) / chain_count_;
  if (resumed_section) load(*resumed_section);
  // The next power of two in mutations per pixel, after the steps done.
  while (steps_done_ * chain_count_ >= next_snapshot_ * pixels_) next_snapshot_ *= 2;
}

uint64_t PssChains::planned() const {
  uint64_t mutations = 0;
  return __builtin_mul_overflow(planned_steps_, chain_count_, &mutations) ? UINT64_MAX : mutations;
}

uint64_t PssChains::sweep_end() const {
  uint64_t mutations = 0;
  return __builtin_mul_overflow(sweep_end_, chain_count_, &mutations) ? UINT64_MAX : mutations;
}

uint64_t PssChains::taken_before() const {
  uint64_t steps = 0;
  for (uint64_t c = first_owned_; c < end_owned_; ++c) steps += chains_[size_t(c)].steps;
  return steps;
}

void PssChains::save(StateWriter& out) const {
  setup_.bootstrap.save(out, stats_);
  out.put<uint64_t>(first_owned_);
  out.put<uint64_t>(end_owned_);
  for (uint64_t c = first_owned_; c < end_owned_; ++c) chains_[size_t(c)].save(out);
  sweeper_.save_stats(out);
  out.put_vector(sweeper_.film_units());
  out.put<uint64_t>(steps_done_);
  out.put<uint8_t>(sweep_active_);
  out.put<uint64_t>(sweep_end_);
  out.put<uint64_t>(rounds_);
  out.put<uint64_t>(logged_);
  if (setup_.normalisation) setup_.normalisation->save(out);
}

void PssChains::load(StateReader& in) {
  const uint64_t first = in.get<uint64_t>(), end = in.get<uint64_t>();
  if (first != first_owned_ || end != end_owned_)
    throw StateError("the saved chains are not this process's share of them");
  for (uint64_t c = first; c < end; ++c) chains_[size_t(c)].load(in, width_, height_);
  sweeper_.load_stats(in);
  const std::vector<int64_t> units = in.get_vector<int64_t>(3 * pixels_ * layers_);
  const bool signed_sums = has_negative_lobes(setup_.scene.description().camera.filter);
  for (const int64_t u : units)
    if (u < 0 && !signed_sums) throw StateError("the saved film is inconsistent");
  sweeper_.load_film_units(units);
  steps_done_ = in.get<uint64_t>();
  sweep_active_ = in.get<uint8_t>();
  sweep_end_ = in.get<uint64_t>();
  rounds_ = in.get<uint64_t>();
  logged_ = in.get<uint64_t>();
  if (setup_.normalisation) setup_.normalisation->load(in);
  in.expect_end();
  // Every count that steers the loop is checked, so that a damaged state can neither
  // loop (nearly) forever nor promise a chain steps it cannot take.
  // (2^40 steps per chain: weeks of rendering; a bound that keeps steps x chains in range.)
  const bool timed = sweeper_.timed();
  bool consistent = sweep_active_ <= 1 && rounds_ > 0 && (rounds_ & (rounds_ - 1)) == 0 &&
                    rounds_ <= (uint64_t(1) << 40) && steps_done_ <= (uint64_t(1) << 40);
  if (consistent && sweep_active_)
    consistent = sweep_end_ > steps_done_ &&
                 (!timed || (sweep_end_ <= planned_steps_ && sweep_end_ - steps_done_ <= rounds_));
  for (uint64_t c = first; consistent && c < end; ++c) {
    const uint64_t steps = chains_[size_t(c)].steps;
    consistent = sweep_active_ ? steps >= steps_done_ && steps <= sweep_end_ : steps == steps_done_;
  }
  if (!consistent) throw StateError("the saved chains' schedule is inconsistent");
  const uint64_t committed = sweep_active_ ? sweep_end_ : steps_done_;
  if (!timed && committed > planned_steps_)
    throw StateError("the checkpoint has " + std::to_string(committed) +
                     " steps per chain done or under way, more than this run's budget of " +
                     std::to_string(planned_steps_) +
                     " (a resumed render may extend the budget, not cut it)");
}

// One step of a chain (Kelemen's estimator; see pss_integrator.h).
void PssChains::step(PssChain& chain, PssSample& proposal, FixedPointFilm& film,
                     std::vector<BlockCounter>& stats) const {
  const bool multiplexed = setup_.options.multiplexed;
  const int min_edges = setup_.min_edges, max_edges = setup_.max_edges;
  const bool shared_films = sweeper_.films_shared();
  const PixelFilter& filter = setup_.scene.camera().filter();
  const int width = width_, height = height_;
  const double p_large = p_large_;
  const bool large = chain.rng.uniform() < p_large;
  chain.u.begin(large);
  setup_.tracer.evaluate(chain.u, chain.rng, chain.length, proposal);
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
                                                       : no_light_row_];
  ++length_stats.proposed;
  length_stats.acceptance_sum += a;
  const double pb = p_large * chain.b;
  const size_t chains_layer = chain.layer * pixels_;
  // The chains' part: the proposal's expected-value weight a.
  splat(film, chains_layer, shared_films, filter, width, height, proposal, a * chain.scale,
        proposal.target + pb);
  if (large) {
    // The independent part, and b's sample.
    if (!setup_.options.drop_large_step_weight)
      splat(film, 0, shared_films, filter, width, height, proposal, chain.scale,
            proposal.target + pb);
    chain.large_steps.add(proposal.target);
  }
  chain.carried += 1.0 - a;
  if (chain.rng.uniform() < a) {
    splat(film, chains_layer, shared_films, filter, width, height, chain.current,
          chain.carried * chain.scale, chain.current.target + pb);
    std::swap(chain.current, proposal);
    chain.carried = 0.0;
    chain.u.accept();
    ++kind_stats.accepted;
    ++length_stats.accepted;
  } else {
    chain.u.reject(setup_.options.keep_coordinate_on_reject);
  }
}

// Sweeps: every chain takes the same number of steps, so that MMLT's per-length scale is
// exact. A budget of mutations is rounded up to whole steps per chain and split at powers
// of two in mutations per pixel (the log's snapshots); a time budget runs sweeps of
// `rounds` steps per chain. A chain's steps depend on its own state alone and the films add
// integers, so the image depends on how many steps each chain took, not on how the sweeps
// were cut: a pause (a checkpoint falling due, a stop) cuts a sweep short, with every
// chain's steps recorded, and the sweep then goes on from there, in this process or a
// resumed one.
void PssChains::begin_sweep(uint64_t rounds) {
  uint64_t sweep = sweeper_.timed() ? rounds : planned_steps_ - steps_done_;
  sweep = std::min(sweep, planned_steps_ - steps_done_);
  // Up to the next power of two in mutations per pixel.
  const uint64_t snapshot_steps = (next_snapshot_ * pixels_ + chain_count_ - 1) / chain_count_;
  if (snapshot_steps > steps_done_) sweep = std::min(sweep, snapshot_steps - steps_done_);
  sweep_end_ = steps_done_ + sweep;
  sweep_active_ = 1;
}

uint64_t PssChains::sweep_block(int block, size_t film) {
  PssSample proposal;
  uint64_t block_steps = 0;
  for (uint64_t c = first_chain_of(uint64_t(block)); c < first_chain_of(uint64_t(block) + 1); ++c) {
    PssChain& chain = chains_[size_t(c)];
    uint64_t& taken = chain.steps;
    const uint64_t before = taken;
    for (; taken < sweep_end_; ++taken) {
      if ((taken & 255) == 255 && interruption::requested()) break;
      step(chain, proposal, sweeper_.films()[film], sweeper_.block_stats(size_t(block)));
    }
    block_steps += taken - before;
    if (interruption::poll(taken - before)) break;
  }
  return block_steps;
}

bool PssChains::behind() const {
  bool incomplete = false;
  for (uint64_t c = first_owned_; c < end_owned_; ++c)
    incomplete |= chains_[size_t(c)].steps < sweep_end_;
  return incomplete;
}

void PssChains::sweep_agreed(bool incomplete, std::span<const uint64_t>) {
  if (incomplete) return;
  sweep_active_ = 0;
  steps_done_ = sweep_end_;
  for (; steps_done_ * chain_count_ >= next_snapshot_ * pixels_; next_snapshot_ *= 2)
    if (setup_.settings.snapshots && steps_done_ * chain_count_ != logged_) {
      logged_ = steps_done_ * chain_count_;
      sweeper_.snapshot(*this, logged_);
    }
}

// A stop mid-sweep leaves chains with different step counts: the image then counts the
// steps actually taken (exact for PSSMLT; MMLT's per-length scale assumes equal counts).
uint64_t PssChains::final_done() {
  std::vector<uint64_t> done_steps = {taken_before()};
  cluster::sum_everywhere(done_steps);
  return done_steps[0];
}

bool PssChains::log_final(uint64_t done) {
  if (done == logged_) return false;
  logged_ = done;
  return true;
}

std::vector<double> PssChains::normalise() {
  const PssBootstrap& bootstrap = setup_.bootstrap;
  PssNormalisation n = pss_normalisation(bootstrap.seeds, chains_, first_owned_, end_owned_);
  const uint64_t primary_samples = n.samples(has_chains_);
  uint64_t bidirectional_samples = 0;
  if (setup_.normalisation) {
    // The lengths' BDPT samples are disjoint from their primary samples, both unbiased for b_k:
    // pooled, each b_k is the mean of all its samples, its error their spread's.
    const NormalisationPass& pass = *setup_.normalisation;
    for (size_t k = 0; k < has_chains_.size(); ++k)
      if (has_chains_[k]) n.lengths[k].add(pass.lengths()[k]);
    bidirectional_samples = pass.sums().samples;
    stats_.normalisation_seconds = pass.seconds();
  }
  std::vector<double> factors = {1.0};
  double b = 0.0;
  for (size_t k = 0; k < has_chains_.size(); ++k)
    if (has_chains_[k]) {
      // Injected: the chains' part scaled by the bootstrap's b_k, as Kelemen's image is.
      const double b_k =
          setup_.options.scale_by_bootstrap_b ? bootstrap.b_length[k] : n.lengths[k].b();
      factors.push_back(b_k / bootstrap.b_length[k]);
      b += b_k;
    }
  stats_.b = b;
  stats_.b_standard_error =
      setup_.options.scale_by_bootstrap_b ? bootstrap.standard_error : n.error(has_chains_);
  stats_.b_samples = primary_samples + bidirectional_samples;
  stats_.b_bidirectional_samples = bidirectional_samples;
  stats_.b_largest_share = n.largest_share(has_chains_);
  uint64_t large_steps = primary_samples;
  for (size_t k = 0; k < has_chains_.size(); ++k)
    if (has_chains_[k]) large_steps -= bootstrap.seeds[k].samples;
  stats_.b_large_steps = large_steps;
  return factors;
}

// The image after `done` steps: the films plus every chain's weight not yet splatted
// (added to a copy), each layer scaled by pixels b_w / steps and its factor (normalise()).
// Under MPI, on rank 0: each rank adds its own chains' films and weights, and the integer
// sums are added over the ranks.
Image PssChains::compose(uint64_t done) {
  std::vector<FixedPointFilm> total(1, FixedPointFilm(pixels_ * layers_));
  FixedPointFilm::load_units(total, sweeper_.film_units());
  const PixelFilter& filter = setup_.scene.camera().filter();
  for (uint64_t c = first_owned_; c < end_owned_; ++c) {
    const PssChain& chain = chains_[size_t(c)];
    splat(total[0], chain.layer * pixels_, false, filter, width_, height_, chain.current,
          chain.carried * chain.scale, chain.current.target + p_large_ * chain.b);
  }
  std::vector<int64_t> units;
  if (!FixedPointFilm::total_units(total, units))
    throw Error("the MCMC film overflowed: too many mutations' worth of weight in one pixel");
  cluster::sum_to_root(units);
  const std::vector<double> factors = normalise();
  const double scale = done > 0 ? double(pixels_) * setup_.bootstrap.b() / double(done) : 0.0;
  std::vector<DVec3> chains_image(pixels_, DVec3(0.0));
  for (size_t layer = 0; layer < layers_; ++layer) {
    const double layer_scale = scale * factors[layer] / FixedPointFilm::kUnitsPerValue;
    const int64_t* u = units.data() + 3 * pixels_ * layer;
    for (uint64_t p = 0; p < pixels_; ++p)
      chains_image[p] +=
          DVec3(double(u[3 * p]), double(u[3 * p + 1]), double(u[3 * p + 2])) * layer_scale;
  }
  Image image = run_.direct_image();
  for (uint64_t p = 0; p < pixels_; ++p) image.pixels[p] += Rgb(chains_image[p]);
  return image;
}

RenderResult PssChains::render(const std::string& name) {
  stats_.chains = chain_count_;
  RenderResult result = sweeper_.run(*this, name);
  stats_.strategies = sweeper_.merged_stats();
  stats_.mutations = result.samples;
  return result;
}

}  // namespace emlt
