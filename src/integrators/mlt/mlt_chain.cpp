#include "emlt/integrators/mlt/mlt_chain.h"

#include <cmath>

#include "emlt/core/error.h"

namespace emlt {

void MltChain::save(const PathCodec& codec, StateWriter& out, bool without_path) const {
  if (without_path) {
    codec.save(Path{}, out);
    out.put(DVec3(0.0));
    out.put(0.0);
    out.put(0.0);
  } else {
    codec.save(current, out);
    out.put(contribution);
    out.put(target);
    out.put(carried);
  }
  out.put(rng.save());
  out.put(steps_taken);
  out.put(sweep_left);
}

void MltChain::load(const PathCodec& codec, StateReader& in) {
  current = codec.load(in);
  contribution = in.get<DVec3>();
  target = in.get<double>();
  carried = in.get<double>();
  rng = Rng::restore(in.get<Rng::State>());
  steps_taken = in.get<uint64_t>();
  sweep_left = in.get<uint64_t>();
  // F(x) is a colour, non-negative: the film turns splats into integers assuming so.
  const auto colour = [](double c) { return std::isfinite(c) && c >= 0.0; };
  if (!std::isfinite(target) || target < 0.0 || !std::isfinite(carried) || carried < 0.0 ||
      !colour(contribution.x) || !colour(contribution.y) || !colour(contribution.z) ||
      (target > 0.0 && current.vertices.empty()))
    throw StateError("a saved chain is inconsistent");
}

}  // namespace emlt
