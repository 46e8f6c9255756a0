// The hyperparameters of --direct-sampler bmc (sampling/bmc_direct_estimator.h). Defaults are
// the fast rule of Marques et al. (TVCG 2013, section 5.4): any noise ratio in [0.4, 1.1] did
// about as well there, and 0.5 was chosen; learned lengthscales followed 1.25 / sqrt(m).
#include "emlt/sampling/sampling_options.h"

namespace emlt {

std::vector<RenderOption> bmc_options() {
  std::vector<RenderOption> o;
  o.push_back(real_option(
      "--bmc-noise", &RenderSettings::bmc_noise, 0.0, true, 10.0, "a number above 0, at most 10",
      "bmc: the GP's noise ratio sigma'_n (default 0.5, the paper's fast rule)"));
  o.push_back(
      real_option("--bmc-lengthscale", &RenderSettings::bmc_lengthscale_factor, 0.1, false, 10.0,
                  "a number from 0.1 to 10",
                  "bmc: the GP's lengthscale l = this / sqrt(m) (default 1.25, the fast rule)"));
  apply_only_where(
      o, [](const RenderSettings& s) { return s.direct_point_set == DirectPointSet::Bmc; });
  return o;
}

}  // namespace emlt
