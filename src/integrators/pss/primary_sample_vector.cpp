#include "emlt/integrators/pss/primary_sample_vector.h"

namespace emlt {

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
