#include "emlt/integrators/registry.h"

#include "emlt/core/error.h"
#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/direct_integrator.h"
#include "emlt/integrators/erpt/erpt_integrator.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/integrators/mlt/mlt_options.h"
#include "emlt/integrators/path_tracer.h"
#include "emlt/integrators/pss/pss_integrator.h"
#include "emlt/integrators/pss/pss_options.h"
#include "emlt/run/integrator.h"
#include "emlt/run/run_options.h"
#include "emlt/sampling/adaptive_options.h"
#include "emlt/sampling/sampling_options.h"

namespace emlt {

// Integrators written in one file, with no header, declare their factory here.
std::unique_ptr<Integrator> make_particle_tracer();

namespace {

struct Registration {
  const char* name;
  std::unique_ptr<Integrator> (*make)();
};

// One line an integrator, in the order the command line lists them.
const Registration kIntegrators[] = {
    {"direct",
     []() -> std::unique_ptr<Integrator> { return std::make_unique<DirectIntegrator>(); }},
    {"pt", []() -> std::unique_ptr<Integrator> { return std::make_unique<PathTracer>(); }},
    {"bdpt",
     []() -> std::unique_ptr<Integrator> { return std::make_unique<BidirectionalPathTracer>(); }},
    {"ptracer", make_particle_tracer},
    {"mlt", []() -> std::unique_ptr<Integrator> { return std::make_unique<MltIntegrator>(); }},
    // MLT with the geometry-aware perturbations as its default mix.
    {"gamlt",
     []() -> std::unique_ptr<Integrator> {
       MltOptions options;
       options.name = "gamlt";
       options.default_mix = kGamltMix;
       return std::make_unique<MltIntegrator>(std::move(options));
     }},
    // MLT with the manifold perturbation (manifold exploration, MEMLT) as its default mix.
    {"memlt",
     []() -> std::unique_ptr<Integrator> {
       MltOptions options;
       options.name = "memlt";
       options.default_mix = kMemltMix;
       options.steps_per_chain = kMemltStepsPerChain;
       return std::make_unique<MltIntegrator>(std::move(options));
     }},
    // MLT run as two swapped ensembles, with the guided strategies.
    {"emlt",
     []() -> std::unique_ptr<Integrator> {
       MltOptions options;
       options.name = "emlt";
       options.default_mix = kEmltMix;
       options.ensemble = true;
       return std::make_unique<MltIntegrator>(std::move(options));
     }},
    {"pssmlt",
     []() -> std::unique_ptr<Integrator> { return std::make_unique<PssMltIntegrator>(); }},
    {"mmlt",
     []() -> std::unique_ptr<Integrator> {
       PssOptions options;
       options.multiplexed = true;
       return std::make_unique<PssMltIntegrator>(options);
     }},
    {"erpt", []() { return make_erpt(); }},
};

// Each part's options, in the order the command line lists them: the run loop's and path
// sampling's (every integrator), bdpt's, the path-space MLT family's with its gamlt and
// emlt groups (the ga-* and emlt-* strategies read theirs in any mix), and pssmlt/mmlt's.
using OptionGroup = const std::vector<RenderOption>& (*)();
const OptionGroup kOptionGroups[] = {run_options,      sampling_options, adaptive_sampler_options,
                                     bdpt_options,     mlt_options,      gamlt_options,
                                     ensemble_options, pss_options,      erpt_options};

}  // namespace

const std::vector<RenderOption>& render_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> all;
    for (const OptionGroup group : kOptionGroups)
      for (const RenderOption& option : group()) {
        bool seen = false;
        for (const RenderOption& o : all) seen = seen || o.flag == option.flag;
        if (!seen) all.push_back(option);
      }
    return all;
  }();
  return options;
}

void apply_integrator_options(const SceneRenderRequest& request, RenderSettings& settings) {
  for (const auto& [flag, text] : request.integrator_options) {
    const RenderOption* found = nullptr;
    for (const RenderOption& option : render_options())
      if (option.flag == flag) found = &option;
    if (!found) throw Error("no integrator has the option " + flag);
    found->set(settings, text);
  }
}

std::vector<std::string> integrator_names() {
  std::vector<std::string> names;
  for (const Registration& r : kIntegrators) names.push_back(r.name);
  return names;
}

std::unique_ptr<Integrator> make_integrator(const std::string& name) {
  const std::string wanted = name == "path" ? "pt" : name;  // Mitsuba's name for it
  for (const Registration& r : kIntegrators)
    if (wanted == r.name) return r.make();
  std::string known;
  for (const auto& n : integrator_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown integrator '" + name + "' (available: " + known + ")");
}

}  // namespace emlt
