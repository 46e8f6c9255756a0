#pragma once
// The state of a primary-sample-space chain (Kelemen et al. 2002): the unit-cube
// coordinates a path sampler reads instead of a random stream. Coordinates are created and
// mutated lazily, when the sampler first reads them in an iteration (Kelemen §4.1):
//   - after a large step was accepted, a coordinate not read since is drawn afresh;
//   - in a large step, every coordinate read is drawn afresh;
//   - in a small step, a coordinate read is perturbed once for every small step it missed
//     (at most kMaxCatchUp times: any symmetric kernel keeps the chain correct, and an
//     unread coordinate does not change f).
// A rejection restores the coordinates the iteration read. Coordinates are laid out in
// `kStreams` interleaved streams (camera subpath, light subpath, connections), so that a
// change in the number of coordinates one subpath reads does not shift the other's.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/core/sample_source.h"
#include "emlt/core/state_io.h"

namespace emlt {

class PrimarySampleVector {
 public:
  static constexpr int kStreams = 3;
  static constexpr uint64_t kMaxCatchUp = 64;
  // More than any path of kMaxPathVertices vertices reads (a checkpoint's bound).
  static constexpr uint64_t kMaxCoordinates = uint64_t(1) << 16;

  // Kelemen's exponential perturbation: a step of s2 * (s1 / s2)^u in either direction,
  // with s2 = sigma and s1 = sigma / 64 (the paper's 1/64 and 1/1024 at sigma = 1/64).
  explicit PrimarySampleVector(float sigma = 1.0f / 64.0f) : sigma_(sigma) {}

  // Starts an iteration; coordinates are then read with value().
  void begin(bool large_step) {
    ++iteration_;
    large_step_ = large_step;
  }
  // Coordinate `index` of the proposal, mutated on first read in this iteration. Inline,
  // with the mutation: a path reads some 30 coordinates, and the calls cost about as much
  // as the arithmetic.
  float value(uint32_t index, Rng& rng) {
    if (index >= coordinates_.size()) [[unlikely]]
      coordinates_.resize(size_t(index) + 1);
    Coordinate& c = coordinates_[index];
    if (c.modified == iteration_) return c.value;  // read before in this iteration
    return mutate(c, rng);
  }
  void accept() {
    if (large_step_) last_large_ = iteration_;
  }
  // `keep_one` (tests only): leaves coordinate 0 as proposed, a classic bug.
  void reject(bool keep_one = false);

  size_t size() const { return coordinates_.size(); }

  // Checkpoints, between iterations (after accept() or reject()): the coordinates with the
  // iteration that last set each, the iteration count and the last accepted large step,
  // which is all a later iteration reads. load() throws StateError for a state no chain
  // could be in (a coordinate outside [0, 1), a stamp from the future).
  void save(StateWriter& out) const;
  void load(StateReader& in);

 private:
  struct Coordinate {
    float value = 0.0f, saved_value = 0.0f;
    uint64_t modified = 0, saved_modified = 0;  // the iteration that last set it
  };
  float perturb(float x, Rng& rng) const {
    // One uniform: its half gives the direction, its position within the half the size.
    const float u = rng.uniform();
    const bool up = u < 0.5f;
    const float v = up ? 2.0f * u : 2.0f * u - 1.0f;
    const float step = sigma_ * std::exp2(-6.0f * v);  // sigma 64^-v
    float y = up ? x + step : x - step;
    // y - floor(y) without the floor (SSE2 has no rounding instruction): a step is at most
    // 1/2, so y lies in (-1/2, 3/2), and y - (-1) is y + 1 to the bit.
    if (y < 0.0f)
      y += 1.0f;
    else if (y >= 1.0f)
      y -= 1.0f;
    return y < 1.0f ? y : 0.0f;
  }
  float mutate(Coordinate& c, Rng& rng) {
    // Not read since the last accepted large step (or never): its value is a fresh one.
    if (c.modified < last_large_ || c.modified == 0) {
      c.value = rng.uniform();
      c.modified = std::max<uint64_t>(last_large_, 1);
    }
    c.saved_value = c.value;
    c.saved_modified = c.modified;
    if (large_step_) {
      c.value = rng.uniform();
    } else {
      const uint64_t missed = std::min(iteration_ - c.modified, kMaxCatchUp);
      for (uint64_t i = 0; i < missed; ++i) c.value = perturb(c.value, rng);
    }
    c.modified = iteration_;
    return c.value;
  }

  std::vector<Coordinate> coordinates_;
  uint64_t iteration_ = 0, last_large_ = 0;
  bool large_step_ = false;
  float sigma_;
};

// The coordinates of one stream as a SampleSource, read in order.
class PrimaryStream final : public SampleSource {
 public:
  PrimaryStream(PrimarySampleVector& vector, Rng& rng, int stream)
      : vector_(vector), rng_(rng), stream_(uint32_t(stream)) {}
  float uniform() final {
    return vector_.value(stream_ + uint32_t(PrimarySampleVector::kStreams) * next_++, rng_);
  }

 private:
  PrimarySampleVector& vector_;
  Rng& rng_;
  uint32_t stream_, next_ = 0;
};

}  // namespace emlt
