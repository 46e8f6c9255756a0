#include "emlt/integrators/pss/pss_chain.h"

#include <cmath>

#include "emlt/core/error.h"

namespace emlt {

namespace {
// More splats than any evaluation makes (BDPT's: one per strategy of a path up to
// kMaxPathVertices vertices); a checkpoint's bound.
constexpr uint64_t kMaxSplats = uint64_t(1) << 16;
}  // namespace

void PssChain::save(StateWriter& out) const {
  u.save(out);
  out.put<double>(current.target);
  out.put_vector(current.splats);
  out.put<double>(carried);
  out.put(rng.save());
  out.put<uint64_t>(steps);
  out.put<NormalisationSums>(large_steps);
}

void PssChain::load(StateReader& in, int width, int height) {
  u.load(in);
  current.target = in.get<double>();
  current.splats = in.get_vector_up_to<PssSplat>(kMaxSplats);
  carried = in.get<double>();
  rng = Rng::restore(in.get<Rng::State>());
  steps = in.get<uint64_t>();
  large_steps = in.get<NormalisationSums>();
  // A chain's state was accepted, so f* > 0; its splats land on the film (their colours
  // are non-negative: the film turns them into integers assuming so).
  // Its large steps are some of its steps.
  bool consistent = std::isfinite(current.target) && current.target > 0.0 &&
                    std::isfinite(carried) && carried >= 0.0 && large_steps.consistent() &&
                    large_steps.samples <= steps;
  for (const PssSplat& s : current.splats)
    consistent = consistent && s.raster.x >= 0.0f && s.raster.x <= float(width) &&
                 s.raster.y >= 0.0f && s.raster.y <= float(height) && std::isfinite(s.value.x) &&
                 s.value.x >= 0.0f && std::isfinite(s.value.y) && s.value.y >= 0.0f &&
                 std::isfinite(s.value.z) && s.value.z >= 0.0f;
  if (!consistent) throw StateError("a saved chain is inconsistent");
}

}  // namespace emlt
