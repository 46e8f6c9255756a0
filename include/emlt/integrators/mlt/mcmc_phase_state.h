#pragma once
// What a checkpointed MCMC render (mlt, gamlt, emlt, pssmlt, mmlt) saves around its chains:
// the phase it stopped in, the seconds so far, the separate direct pass's state, and the
// chains' own section, which each driver writes and reads itself.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "emlt/core/state_io.h"
#include "emlt/run/pixel_state.h"

namespace emlt {

struct McmcPhaseState {
  PixelRenderState direct;    // the separate direct image's pass (with --direct separate)
  std::string chain_section;  // a resumed chains section, until the driver has loaded it
  double earlier_seconds = 0.0;

  // Reads a saved state; an unknown phase or damaged data throws StateError.
  void load(std::string_view saved, bool direct_separate, int width, int height);
  // Writes the state after `seconds`; `chains` writes the chains' section (null: the chains
  // have not started, or a resumed section not yet loaded is written back as it was).
  void save(StateWriter& out, double seconds, bool direct_separate,
            const std::function<void(StateWriter&)>& chains) const;
};

}  // namespace emlt
