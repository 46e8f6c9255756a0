#include "emlt/sampling/adaptive_options.h"

namespace emlt {

const std::vector<RenderOption>& adaptive_sampler_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> o;
    o.push_back(whole_option("--adaptive-initial", &RenderSettings::adaptive_initial, 1, 1 << 16,
                             "a whole number from 1 to 65536",
                             "Adaptive: directions placed in equal cells before the error "
                             "estimate decides (1: the paper's single root cell)"));
    o.push_back(real_option("--adaptive-robustness", &RenderSettings::adaptive_robustness, 0.0,
                            false, 1e6, "a number from 0 to 1000000",
                            "Adaptive: the slope added to each cell's derivative, in units of "
                            "the mean value times the cell's edge"));
    RenderOption map;
    map.flag = "--adaptive-parametrisation";
    map.help = "Adaptive: the square's map onto directions: cosine (diffuse BRDF's) | global";
    map.values = {OptionValues::Kind::Word, 0, 0, false, {"cosine", "global"}, "cosine or global"};
    map.assign = [](RenderSettings& s, const std::string& text) {
      s.adaptive_parametrisation =
          text == "global" ? AdaptiveParametrisation::Global : AdaptiveParametrisation::Cosine;
    };
    map.recorded = [](const RenderSettings& s) {
      return std::string(s.adaptive_parametrisation == AdaptiveParametrisation::Global ? "global"
                                                                                       : "cosine");
    };
    o.push_back(map);
    apply_only_where(
        o, [](const RenderSettings& s) { return s.direct_point_set == DirectPointSet::Adaptive; });
    return o;
  }();
  return options;
}

}  // namespace emlt
