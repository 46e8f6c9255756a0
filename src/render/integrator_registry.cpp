#include "emlt/core/error.h"
#include "emlt/render/bdpt.h"
#include "emlt/render/direct_integrator.h"
#include "emlt/render/integrator.h"
#include "emlt/render/path_tracer.h"
#include "emlt/mcmc/mlt_integrator.h"
#include "emlt/mcmc/pss_integrator.h"

namespace emlt {

std::vector<std::string> integrator_names() {
  return {"direct", "pt", "bdpt", "mlt", "gamlt", "emlt", "pssmlt", "mmlt"};
}

std::unique_ptr<Integrator> make_integrator(const std::string& name) {
  if (name == "direct") return std::make_unique<DirectIntegrator>();
  if (name == "pt" || name == "path") return std::make_unique<PathTracer>();
  if (name == "bdpt") return std::make_unique<BidirectionalPathTracer>();
  if (name == "mlt") return std::make_unique<MltIntegrator>();
  if (name == "gamlt") {  // MLT with the geometry-aware perturbations as its default mix
    MltOptions options;
    options.name = "gamlt";
    options.default_mix = kGamltMix;
    return std::make_unique<MltIntegrator>(std::move(options));
  }
  if (name == "emlt") {  // MLT run as two swapped ensembles, with the guided strategies
    MltOptions options;
    options.name = "emlt";
    options.default_mix = kEmltMix;
    options.ensemble = true;
    return std::make_unique<MltIntegrator>(std::move(options));
  }
  if (name == "pssmlt") return std::make_unique<PssMltIntegrator>();
  if (name == "mmlt") {
    PssOptions options;
    options.multiplexed = true;
    return std::make_unique<PssMltIntegrator>(options);
  }
  std::string known;
  for (const auto& n : integrator_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown integrator '" + name + "' (available: " + known + ")");
}

}  // namespace emlt
