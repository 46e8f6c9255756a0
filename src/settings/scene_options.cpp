#include "emlt/settings/scene_options.h"

#include <algorithm>

#include "emlt/core/error.h"

namespace emlt {

std::string SceneFileOption::json_key() const {
  std::string key = option.flag.substr(option.flag.find_first_not_of('-'));
  std::replace(key.begin(), key.end(), '-', '_');
  return key;
}

const std::vector<SceneFileOption>& scene_file_options() {
  static const std::vector<SceneFileOption> options = [] {
    RenderOption spp =
        whole_option("--spp", &RenderSettings::spp, 1, kMaxSpp,
                     "a whole number from 1 to 2^24 (about 16.8 million)", "Samples per pixel");
    spp.recorded = nullptr;  // the budget may grow on a resume
    // Mitsuba accepts any maxDepth and rrDepth >= 1 (and refuses a maxDepth of 0, which emlt
    // renders as black); past 100000 segments no path survives Russian roulette in any
    // scene, and a longer bound only hides a typo.
    RenderOption max_depth = whole_option("--max-depth", &RenderSettings::max_depth, -1, 100000,
                                          "a whole number from 0 to 100000, or -1 for unlimited",
                                          "Longest path in segments (-1 = unlimited)");
    RenderOption rr_depth = whole_option(
        "--rr-depth", &RenderSettings::rr_depth, 1, 100000, "a whole number from 1 to 100000",
        "Segments before Russian roulette starts (bidirectional subpaths: one fewer, as in "
        "Mitsuba)");
    RenderOption hide_emitters = switch_option(
        "--hide-emitters", &RenderSettings::hide_emitters, "false", "true",
        "Leave out light that reaches the camera without scattering (lights and the sky seen "
        "directly)");
    return std::vector<SceneFileOption>{
        {spp, "sampleCount", MitsubaElement::Sampler},
        {max_depth, "maxDepth", MitsubaElement::Integrator},
        {rr_depth, "rrDepth", MitsubaElement::Integrator},
        {hide_emitters, "hideEmitters", MitsubaElement::Integrator},
    };
  }();
  return options;
}

const SceneFileOption& scene_file_option(std::string_view flag) {
  for (const SceneFileOption& o : scene_file_options())
    if (o.option.flag == flag) return o;
  throw Error("no scene file sets " + std::string(flag));
}

}  // namespace emlt
