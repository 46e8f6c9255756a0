#include "emlt/mcmc/primary_sample_vector.h"

#include <algorithm>
#include <cmath>

namespace emlt {

float PrimarySampleVector::perturb(float x, Rng& rng) const {
  // One uniform: its half gives the direction, its position within the half the size.
  const float u = rng.uniform();
  const bool up = u < 0.5f;
  const float v = up ? 2.0f * u : 2.0f * u - 1.0f;
  const float step = sigma_ * std::exp2(-6.0f * v);  // sigma 64^-v
  float y = up ? x + step : x - step;
  y -= std::floor(y);
  return y < 1.0f ? y : 0.0f;
}

float PrimarySampleVector::mutate(uint32_t index, Rng& rng) {
  if (index >= coordinates_.size()) coordinates_.resize(size_t(index) + 1);
  Coordinate& c = coordinates_[index];
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

void PrimarySampleVector::reject(bool keep_one) {
  // The coordinates this iteration read are those it stamped (a vector is a few dozen long).
  for (size_t index = keep_one ? 1 : 0; index < coordinates_.size(); ++index) {
    Coordinate& c = coordinates_[index];
    if (c.modified != iteration_) continue;
    c.value = c.saved_value;
    c.modified = c.saved_modified;
  }
  // The rejected iteration did not happen: the next small step perturbs from the same
  // count of missed steps.
  --iteration_;
}

void PrimarySampleVector::save(StateWriter& out) const {
  out.put(iteration_);
  out.put(last_large_);
  out.put<uint8_t>(large_step_);
  out.put<uint64_t>(coordinates_.size());
  for (const Coordinate& c : coordinates_) {
    out.put(c.value);
    out.put(c.modified);
  }
}

void PrimarySampleVector::load(StateReader& in) {
  iteration_ = in.get<uint64_t>();
  last_large_ = in.get<uint64_t>();
  large_step_ = in.get<uint8_t>() != 0;
  // A path reads a few coordinates per vertex from each stream.
  const uint64_t count = in.get<uint64_t>();
  if (count > kMaxCoordinates || count > in.remaining() / (sizeof(float) + sizeof(uint64_t)))
    throw StateError("a chain's primary sample is longer than possible");
  if (last_large_ > iteration_) throw StateError("a chain's primary sample is inconsistent");
  coordinates_.assign(size_t(count), Coordinate{});
  for (Coordinate& c : coordinates_) {
    c.value = in.get<float>();
    c.modified = in.get<uint64_t>();
    // (Between iterations the saved copies are dead: the next read of a coordinate in an
    // iteration sets them before anything can restore them.)
    c.saved_value = c.value;
    c.saved_modified = c.modified;
    if (!(c.value >= 0.0f && c.value < 1.0f) || c.modified > iteration_)
      throw StateError("a chain's primary sample is inconsistent");
  }
}

}  // namespace emlt
