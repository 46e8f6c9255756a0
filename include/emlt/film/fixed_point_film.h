#pragma once
// The film MCMC chains splat into. Each value is rounded to a multiple of 2^-24 and added as
// a 64-bit integer, so a pixel's sum does not depend on the order of its additions: chains
// running on any threads, in any interleaving, give the same bits. That is what lets the
// driver keep one film per thread instead of one per fixed block of chains (16 films of
// double RGB were 0.8 GB at 1920 x 1080 and 3.2 GB at 4K, whatever the thread count).
//
// Range and resolution. A splat is weight * F / f*, at most 14 per unit of weight in size
// (F / luminance(F) is largest for pure blue, 1 / 0.0722; negative only where a
// reconstruction filter's negative lobe weighs it), and all splats of a render
// carry one unit of weight per mutation (plus the chains' weight not yet splatted). A pixel
// holds 2^39 = 5.5e11 units before its sum could overflow, i.e. 4e10 mutations' worth of
// weight landing in that one pixel; an overflow is detected and reported rather than
// written. Rounding changes a splat by at most 3e-8, far below any
// pixel's Monte Carlo error, and the errors of many splats average out.
#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "emlt/core/math.h"

namespace emlt {

// Cache-line aligned: the driver keeps one film per thread side by side in a vector, and a
// film's header (the pointer every splat reads) must not share a line with its neighbour's.
class alignas(64) FixedPointFilm {
 public:
  static constexpr double kUnitsPerValue = 16777216.0;  // 2^24, for splats of colour

  // `units_per_value`: the resolution, for tallies of another range (a power of two keeps
  // the conversion exact).
  explicit FixedPointFilm(size_t pixels, double units_per_value = kUnitsPerValue)
      : sums_(3 * pixels, 0), units_per_value_(units_per_value) {}

  // Adds a finite value (negative under a filter's negative lobe). `shared`: other threads
  // add to this film at the same time (atomic additions); otherwise plain ones.
  void add(size_t pixel, const DVec3& value, bool shared) {
    int64_t* sum = &sums_[3 * pixel];
    bool overflow = false;
    const int64_t units[3] = {to_units(value.x, overflow), to_units(value.y, overflow),
                              to_units(value.z, overflow)};
    if (shared) {
      for (int c = 0; c < 3; ++c) {
        const int64_t before =
            std::atomic_ref<int64_t>(sum[c]).fetch_add(units[c], std::memory_order_relaxed);
        int64_t after;
        overflow |= __builtin_add_overflow(before, units[c], &after);
      }
      if (overflow) std::atomic_ref<int64_t>(overflows_).fetch_add(1, std::memory_order_relaxed);
    } else {
      for (int c = 0; c < 3; ++c) overflow |= __builtin_add_overflow(sum[c], units[c], &sum[c]);
      // Written only when it happens: a store on every splat made the films' headers
      // ping-pong between the cores (2 threads: 7 % more CPU time for the same chains).
      if (overflow) [[unlikely]]
        ++overflows_;
    }
  }

  // Checkpoints: every film's sums added into one exact integer array (the films a chain
  // splats into depend on the threads; their sum does not), and its reload into `films`,
  // all into the first. False when the sum leaves the range.
  static bool total_units(std::span<const FixedPointFilm> films, std::vector<int64_t>& out) {
    out.assign(films.empty() ? 0 : films[0].sums_.size(), 0);
    for (const FixedPointFilm& film : films) {
      if (film.overflowed()) return false;
      for (size_t i = 0; i < out.size(); ++i)
        if (__builtin_add_overflow(out[i], film.sums_[i], &out[i])) return false;
    }
    return true;
  }
  static void load_units(std::span<FixedPointFilm> films, const std::vector<int64_t>& units) {
    for (FixedPointFilm& film : films) {
      std::fill(film.sums_.begin(), film.sums_.end(), 0);
      film.overflows_ = 0;
    }
    if (!films.empty()) films[0].sums_ = units;
  }
  size_t units_size() const { return sums_.size(); }

  void prefetch(size_t pixel) const { __builtin_prefetch(&sums_[3 * pixel], 1); }

  // Whether some pixel's sum left the range.
  bool overflowed() const { return overflows_ > 0; }

  // The sum of every film's pixel (films of one resolution), exactly (integers), then
  // converted once; false if it leaves the range.
  static bool total(std::span<const FixedPointFilm> films, size_t pixel, DVec3& out) {
    int64_t sum[3] = {0, 0, 0};
    for (const FixedPointFilm& film : films)
      for (int c = 0; c < 3; ++c)
        if (__builtin_add_overflow(sum[c], film.sums_[3 * pixel + size_t(c)], &sum[c]))
          return false;
    const double units = films.empty() ? kUnitsPerValue : films[0].units_per_value_;
    out = DVec3(double(sum[0]), double(sum[1]), double(sum[2])) / units;
    return true;
  }

 private:
  int64_t to_units(double value, bool& overflow) const {
    // A single value beyond the range (or not a number) counts as an overflow by itself.
    // Rounded to the nearest unit on both sides of zero (a cast alone would round negative
    // splats towards zero and bias them).
    const double scaled = std::floor(value * units_per_value_ + 0.5);
    if (std::abs(scaled) < 9.0e18) return int64_t(scaled);
    overflow = true;
    return 0;
  }

  std::vector<int64_t> sums_;
  double units_per_value_;
  int64_t overflows_ = 0;  // additions that left the range
};

}  // namespace emlt
