#pragma once
// The frame around every MCMC driver's chains (mlt, gamlt, emlt, pssmlt, mmlt): the render's
// clock, which carries the seconds of the runs before a resume and can leave out the time
// spent writing snapshots; the checkpoint state it resumed from and saves
// (mcmc_phase_state.h); and the separate direct-light pass, which keeps pace with the
// chains so that a render stopped at any moment has both parts of the image.
#include <chrono>
#include <functional>
#include <string>

#include "emlt/core/state_io.h"
#include "emlt/integrators/mlt/mcmc_phase_state.h"
#include "emlt/run/chain_frame.h"
#include "emlt/run/integrator.h"
#include "emlt/run/render_control.h"
#include "emlt/settings/settings.h"

namespace emlt {

class Scene;
struct MltStatistics;

class McmcRun final : public ChainFrame {
 public:
  // Loads a resumed render's state (settings.control); damaged state throws StateError.
  McmcRun(const Scene& scene, const RenderSettings& settings);

  // The camera's pixels, and a result with their image black: what the chains add to.
  uint64_t pixels() const { return uint64_t(width_) * uint64_t(height_); }
  RenderResult black_result() const;

  // Seconds since the first run began, the runs before a resume included.
  double elapsed() const override;
  // elapsed() less the time written off (snapshots): what budgets and reports count.
  double counted_seconds() const override { return elapsed() - written_off_; }
  void write_off(double seconds) override { written_off_ += seconds; }

  RenderControl* control() const override { return control_; }
  // A resumed render's chains section until the driver has loaded it (empty: fresh chains).
  std::string& chain_section() { return phase_.chain_section; }

  // Writes the checkpoint; `chains` writes the chains' section (null: not started yet).
  void save(StateWriter& out, const std::function<void(StateWriter&)>& chains) const override;
  // The checkpoint of a render whose chains have not started (or are written back as loaded).
  void save_before_chains(StateWriter& out) const { save(out, nullptr); }
  // Pauses for a checkpoint (or a stop) requested before the chains started.
  void pause_before_chains() const;
  // Ends a render without chains (nothing for them to do, or cut short before them).
  void finish_before_chains() const;

  // A render that ends before its chains, `result` then its whole answer (the direct light,
  // rendered to the end of its budget), with its seconds: there is nothing for them to do
  // (no path length is left to them, or the bootstrap found no light: then `warning` on
  // rank 0).
  void end_without_chains(RenderResult& result, MltStatistics& stats,
                          const char* warning = nullptr);
  // Whether a stop cut any rank's bootstrap short (a collective call): then nothing of it is
  // kept, as a resumed render runs it again to the same bits, and `result` is the render's
  // whole answer (with the direct light so far).
  bool stopped_in_bootstrap(bool interrupted, RenderResult& result, MltStatistics& stats);

  // With settings.direct_separate, the direct light (paths of one and two segments, as
  // Mitsuba renders them by default) rendered up to `share` of its budget
  // (render_direct_pass), calling `on_pause` at a checkpoint or stop inside it; false when
  // a stop cut it short. Without it, nothing to do: true. A collective call.
  bool direct_up_to(double share, const std::function<void()>& on_pause) override;
  // The direct image so far, each pixel the mean of its samples (black without
  // --direct separate), complete on rank 0 (a collective call).
  Image direct_image() const override;
  // The direct pass's samples per pixel and seconds into the statistics.
  void direct_statistics(MltStatistics& stats) const;

 private:
  const RenderSettings& settings_;
  int width_, height_;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  RenderControl* control_;
  const Scene& scene_;
  mutable McmcPhaseState phase_;  // the direct pass's state advances inside direct_up_to
  int direct_spp_ = 0;
  double direct_seconds_ = 0.0;
  double written_off_ = 0.0;
};

}  // namespace emlt
