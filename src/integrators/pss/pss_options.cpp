#include "emlt/integrators/pss/pss_options.h"

namespace emlt {

const std::vector<RenderOption>& pss_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> o = {
      switch_option("--pss-tracer", &RenderSettings::pss_bdpt, "pt", "bdpt",
                    "pssmlt: the sampler the primary samples drive: pt | bdpt"),
      real_option("--large-step", &RenderSettings::large_step_probability, 0.0, false, 1.0,
                  "a probability from 0 to 1",
                  "pssmlt/mmlt: probability of a large step (default 0.3)"),
      real_option("--pss-sigma", &RenderSettings::pss_sigma, 0.0, true, 0.5,
                  "a number above 0, at most 0.5",
                  "pssmlt/mmlt: largest small-step perturbation of a coordinate (default 1/64)"),
    };
    apply_only_where(o, [](const RenderSettings& s) {
      return s.integrator == "pssmlt" || s.integrator == "mmlt";
    });
    return o;
  }();
  return options;
}

}  // namespace emlt
