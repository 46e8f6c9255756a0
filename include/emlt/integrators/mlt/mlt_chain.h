#pragma once
// One chain of path-space MLT (mlt, gamlt, emlt): its current path and what the step and
// the image need of it, and how a checkpoint keeps it.
#include <cstdint>

#include "emlt/core/rng.h"
#include "emlt/core/state_io.h"
#include "emlt/mcmc/strategy_mix.h"
#include "emlt/path/path_state.h"

namespace emlt {

struct MltChain {
  Path current;
  DVec3 contribution{0.0};      // F(x)
  double target = 0.0;          // f*(x)
  double carried = 0.0;         // expected-value weight not yet splatted for x
  StrategyMask applicable = 0;  // which strategies apply to `current`
  Rng rng;
  uint64_t steps_taken = 0;  // keys EMLT's choice of guides (ensemble_guides.h)
  uint64_t sweep_left = 0;   // steps still to take in the sweep under way
  bool moved = false;        // accepted a proposal since packed for the other ranks (EMLT, MPI)

  // `without_path`: a guide copy of another rank's chain (EMLT under MPI), which is no chain
  // to resume from: saved as a chain without a path, its owner sending it again on resume.
  void save(const PathCodec& codec, StateWriter& out, bool without_path) const;
  // Everything but `applicable`, which follows from the path (and is checked that way);
  // an inconsistent chain throws StateError.
  void load(const PathCodec& codec, StateReader& in);
};

}  // namespace emlt
