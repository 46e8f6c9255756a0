#include "emlt/mcmc/mcmc_run.h"

#include <cstdio>

#include "emlt/core/cluster.h"
#include "emlt/mcmc/mlt_integrator.h"
#include "emlt/render/direct_integrator.h"
#include "emlt/render/interruption.h"
#include "emlt/scene/scene.h"

namespace emlt {

McmcRun::McmcRun(const Scene& scene, const RenderSettings& settings)
    : settings_(settings),
      width_(scene.camera().width()),
      height_(scene.camera().height()),
      control_(settings.control) {
  if (control_ && !control_->resume_state().empty())
    phase_.load(control_->resume_state(), settings.direct_separate, width_, height_);
}

RenderResult McmcRun::black_result() const {
  RenderResult result;
  result.image = Image(width_, height_);
  return result;
}

double McmcRun::elapsed() const {
  return phase_.earlier_seconds +
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void McmcRun::save(StateWriter& out, const std::function<void(StateWriter&)>& chains) const {
  phase_.save(out, counted_seconds(), settings_.direct_separate, chains);
}

void McmcRun::pause_before_chains() const {
  RenderControl::pause(control_, [this](StateWriter& out) { save_before_chains(out); });
}

void McmcRun::finish_before_chains() const {
  RenderControl::finish(control_, [this](StateWriter& out) { save_before_chains(out); });
}

void McmcRun::end_without_chains(RenderResult& result, MltStatistics& stats,
                                 const char* warning) const {
  // Every rank holds the same bootstrap; one warning is enough.
  if (warning && cluster::is_root()) std::fprintf(stderr, "emlt: warning: %s\n", warning);
  finish_before_chains();
  result.seconds = stats.seconds = elapsed();
}

bool McmcRun::stopped_in_bootstrap(bool interrupted, RenderResult& result,
                                   MltStatistics& stats) const {
  // Every rank knows whether any rank's bootstrap was cut short (bootstrap.cpp); the
  // agreement makes every rank's stop request and checkpoint the same.
  interruption::agree(interrupted);
  if (!interrupted) return false;
  pause_before_chains();
  result.interrupted = true;
  result.stopped_in = "the bootstrap";
  result.seconds = stats.seconds = elapsed();
  return true;
}

bool McmcRun::direct_pass(const Scene& scene, RenderResult& result, MltStatistics& stats) const {
  if (!settings_.direct_separate) return true;
  const RenderResult direct =
      render_direct_pass(scene, settings_, phase_.direct, [this] { pause_before_chains(); });
  result.image = direct.image;
  stats.direct_spp = direct.samples_per_pixel;
  stats.direct_seconds = direct.seconds;
  if (!direct.interrupted) return true;
  result.interrupted = true;
  result.stopped_in = "the direct-light pass";
  result.per_pixel = 0.0;
  result.seconds = stats.seconds = elapsed();
  return false;
}

}  // namespace emlt
