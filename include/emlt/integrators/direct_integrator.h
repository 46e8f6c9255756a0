#pragma once
#include <functional>

#include "emlt/core/rng.h"
#include "emlt/run/integrator.h"

namespace emlt {
struct PixelRenderState;
}

namespace emlt {

class DirectIntegrator final : public Integrator {
 public:
  std::string name() const override { return "direct"; }
  RenderResult render(const Scene& scene, const RenderSettings& settings,
                      ProgressReporter& progress) const override;
  // Radiance along one camera ray (exposed for tests). `pixel_alpha` in [0, 1]: the pixel's
  // prepared light share for --mis second-order (mis_alpha_map.h), unless --mis-alpha fixes
  // one; negative: estimated online.
  static Rgb radiance(const Scene& scene, const RenderSettings& settings, const Ray& ray, Rng& rng,
                      double pixel_alpha = -1.0);
};

// The image of paths of one and two segments (emitters seen directly, direct light) that an
// MCMC integrator renders first under `--direct separate`, as Mitsuba does by default; its
// chains then never visit such paths. `--direct-spp` samples per pixel, or as many as the
// mutations per pixel, or under a pure time budget a fixed share of the time (whole passes:
// with a fixed 16 samples per pixel the direct image's noise dominated the door scene's
// error, MSE 1.1-2.0e-4 in 5 s against 1.0-1.5e-5 with a few hundred samples). `share`:
// how much of that budget to have done when the call returns, so that the pass can keep
// pace with the chains in slices; its image is the same bits however it was sliced.
// Continues from `state` and calls `on_pause` at a checkpoint or stop, as render_pixels
// does.
RenderResult render_direct_pass(const Scene& scene, const RenderSettings& settings,
                                PixelRenderState& state, const std::function<void()>& on_pause,
                                double share = 1.0);

}  // namespace emlt
