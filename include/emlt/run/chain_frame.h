#pragma once
// What the chain sweeper (chain_sweeper.h) needs from the frame an MCMC driver keeps around
// its chains (integrators/mlt/mcmc_run.h): the render's clock, its checkpoint, and the
// separate direct-light pass that keeps pace with the chains. An interface, so that the
// loop sits below the integrators that use it.
#include <functional>

#include "emlt/core/state_io.h"
#include "emlt/image/image.h"

namespace emlt {

class RenderControl;

class ChainFrame {
 public:
  virtual ~ChainFrame() = default;

  // Seconds since the first run began, the runs before a resume included.
  virtual double elapsed() const = 0;
  // elapsed() less the time written off (snapshots): what budgets and reports count.
  virtual double counted_seconds() const = 0;
  virtual void write_off(double seconds) = 0;

  virtual RenderControl* control() const = 0;
  // Writes the checkpoint; `chains` writes the chains' section (null: not started yet).
  virtual void save(StateWriter& out, const std::function<void(StateWriter&)>& chains) const = 0;

  // The direct light rendered up to `share` of its budget, calling `on_pause` at a
  // checkpoint or stop inside it; false when a stop cut it short (a collective call).
  virtual bool direct_up_to(double share, const std::function<void()>& on_pause) = 0;
  // The direct image so far, complete on rank 0 (a collective call).
  virtual Image direct_image() const = 0;
};

}  // namespace emlt
