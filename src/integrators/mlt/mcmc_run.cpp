#include "emlt/integrators/mlt/mcmc_run.h"

#include <cstdio>

#include "emlt/core/cluster.h"
#include "emlt/core/interruption.h"
#include "emlt/integrators/direct_integrator.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/scene/scene.h"

namespace emlt {

McmcRun::McmcRun(const Scene& scene, const RenderSettings& settings)
    : settings_(settings),
      width_(scene.camera().width()),
      height_(scene.camera().height()),
      control_(settings.control),
      scene_(scene) {
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

void McmcRun::end_without_chains(RenderResult& result, MltStatistics& stats, const char* warning) {
  // Every rank holds the same bootstrap; one warning is enough.
  if (warning && cluster::is_root()) std::fprintf(stderr, "emlt: warning: %s\n", warning);
  if (direct_up_to(1.0, [this] { pause_before_chains(); })) {
    finish_before_chains();
  } else {
    result.interrupted = true;
    result.stopped_in = "the direct-light pass";
  }
  result.image = direct_image();
  direct_statistics(stats);
  result.seconds = stats.seconds = elapsed();
}

bool McmcRun::stopped_in_bootstrap(bool interrupted, RenderResult& result, MltStatistics& stats) {
  // Every rank knows whether any rank's bootstrap was cut short (bootstrap.cpp); the
  // agreement makes every rank's stop request and checkpoint the same.
  interruption::agree(interrupted);
  if (!interrupted) return false;
  pause_before_chains();
  result.interrupted = true;
  result.stopped_in = "the bootstrap";
  result.image = direct_image();
  direct_statistics(stats);
  result.seconds = stats.seconds = elapsed();
  return true;
}

bool McmcRun::direct_up_to(double share, const std::function<void()>& on_pause) {
  if (!settings_.direct_separate) return true;
  const RenderResult direct = render_direct_pass(scene_, settings_, phase_.direct, on_pause, share);
  // The next slice continues from here.
  phase_.direct.resumed = true;
  direct_spp_ = direct.samples_per_pixel;
  direct_seconds_ = direct.seconds;
  return !direct.interrupted;
}

Image McmcRun::direct_image() const {
  if (!settings_.direct_separate || phase_.direct.sums.empty()) return Image(width_, height_);
  return phase_.direct.totals().image(width_, height_);
}

void McmcRun::direct_statistics(MltStatistics& stats) const {
  stats.direct_spp = direct_spp_;
  stats.direct_seconds = direct_seconds_;
}

}  // namespace emlt
