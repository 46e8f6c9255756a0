#include "emlt/sampling/sampling_options.h"

#include "emlt/settings/scene_options.h"

namespace emlt {

const std::vector<RenderOption>& sampling_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> o;
    for (const char* flag : {"--max-depth", "--rr-depth", "--hide-emitters"})
      o.push_back(scene_file_option(flag).option);
    RenderOption mis;
    mis.flag = "--mis";
    mis.help = "MIS heuristic";
    mis.values = {OptionValues::Kind::Word, 0, 0, false, {"balance", "power"}, "balance or power"};
    mis.assign = [](RenderSettings& s, const std::string& text) {
      s.mis = text == "balance" ? MisHeuristic::Balance : MisHeuristic::Power;
    };
    mis.recorded = [](const RenderSettings& s) { return std::string(to_string(s.mis)); };
    o.push_back(mis);
    o.push_back(whole_option("--direct-samples", &RenderSettings::direct_samples, 1, 1 << 16,
                             "a whole number from 1 to 65536",
                             "Light and BSDF samples per direct-lighting estimate"));
    RenderOption points;
    points.flag = "--direct-sampler";
    points.help = "Point set for direct lighting: independent | fibonacci";
    points.values = {OptionValues::Kind::Word,  0, 0, false, {"independent", "fibonacci"},
                     "independent or fibonacci"};
    points.assign = [](RenderSettings& s, const std::string& text) {
      s.direct_point_set =
          text == "fibonacci" ? DirectPointSet::Fibonacci : DirectPointSet::Independent;
    };
    points.recorded = [](const RenderSettings& s) {
      return std::string(s.direct_point_set == DirectPointSet::Fibonacci ? "fibonacci"
                                                                         : "independent");
    };
    o.push_back(points);
    return o;
  }();
  return options;
}

}  // namespace emlt
