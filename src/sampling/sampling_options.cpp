#include "emlt/sampling/sampling_options.h"

namespace emlt {

const std::vector<RenderOption>& sampling_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> o;
    o.push_back(whole_option("--max-depth", &RenderSettings::max_depth, -1, 100000,
                             "a whole number from 0 to 100000, or -1 for unlimited",
                             "Longest path in segments (-1 = unlimited)"));
    o.back().mitsuba = "maxDepth";
    o.push_back(whole_option("--rr-depth", &RenderSettings::rr_depth, 1, 100000,
                             "a whole number from 1 to 100000",
                             "Segments before Russian roulette starts (bidirectional subpaths: "
                             "one fewer, as in Mitsuba)"));
    o.back().mitsuba = "rrDepth";
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
