#pragma once
// Random streams. Every chain, pixel or tile owns a stream derived from (seed, index), so
// results never depend on which thread ran the work.
#include <cstdint>

#include "emlt/core/math.h"

namespace emlt {

// SplitMix64 finaliser: decorrelates nearby integers (seed, seed+1, ...).
inline uint64_t mix_bits(uint64_t v) {
  v += 0x9e3779b97f4a7c15ull;
  v = (v ^ (v >> 30)) * 0xbf58476d1ce4e5b9ull;
  v = (v ^ (v >> 27)) * 0x94d049bb133111ebull;
  return v ^ (v >> 31);
}

// A stream key from a user seed and a work-item index (pixel, chain, ...).
inline uint64_t derive_stream_seed(uint64_t seed, uint64_t index) {
  return mix_bits(mix_bits(seed) ^ (index * 0xd1b54a32d192ed03ull));
}

// PCG32 (O'Neill 2014): 64-bit LCG state with an output permutation; the stream id
// selects one of 2^63 independent sequences.
class Rng {
 public:
  Rng() : Rng(0, 0) {}
  Rng(uint64_t seed, uint64_t stream) {
    state_ = 0;
    increment_ = (stream << 1u) | 1u;
    next_u32();
    state_ += mix_bits(seed);
    next_u32();
  }
  // Convenience: stream for work item `index` of a render seeded with `seed`.
  static Rng for_item(uint64_t seed, uint64_t index) {
    return Rng(derive_stream_seed(seed, index), index);
  }

  // The exact position in the stream, for checkpoints: restore(save()) continues the very
  // same sequence.
  struct State {
    uint64_t state, increment;
  };
  State save() const { return {state_, increment_}; }
  static Rng restore(const State& s) {
    Rng rng;
    rng.state_ = s.state;
    rng.increment_ = s.increment | 1u;  // PCG's increment is odd
    return rng;
  }

  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + increment_;
    const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }
  // Uniform in [0, 1): 24 random mantissa bits, never 1.
  float uniform() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }
  double uniform_double() {
    const uint64_t hi = next_u32(), lo = next_u32();
    return static_cast<double>(((hi << 32) | lo) >> 11) * 0x1p-53;
  }
  Vec2 uniform2() {
    const float a = uniform();
    return {a, uniform()};
  }
  // Uniform integer in [0, n) without modulo bias worth caring about for n << 2^32.
  uint32_t uniform_index(uint32_t n) {
    return static_cast<uint32_t>((static_cast<uint64_t>(next_u32()) * n) >> 32);
  }

 private:
  uint64_t state_;
  uint64_t increment_;
};

}  // namespace emlt
