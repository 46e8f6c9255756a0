#include "emlt/run/run_options.h"

#include <cstdint>

#include "emlt/settings/scene_options.h"

namespace emlt {

const std::vector<RenderOption>& run_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> o;
    o.push_back(scene_file_option("--spp").option);
    o.push_back(real_option("--time", &RenderSettings::time_limit_s, 0.0, true, kMaxTimeSeconds,
                            "a positive number of seconds, at most 30 days",
                            "Time budget in seconds (renders until spent)"));
    o.back().recorded = nullptr;
    RenderOption seed;
    seed.flag = "--seed";
    seed.help = "Random seed (same seed, same image)";
    seed.values = {OptionValues::Kind::Whole,          0.0, double(INT64_MAX), false, {},
                   "a whole number from 0 to 2^63 - 1"};
    seed.assign = [](RenderSettings& s, const std::string& text) { s.seed = std::stoull(text); };
    seed.recorded = [](const RenderSettings& s) { return recorded_number(s.seed); };
    o.push_back(seed);
    // The image is bit-identical at any thread count.
    o.push_back(whole_option("--threads", &RenderSettings::threads, 0, kMaxThreads,
                             "1..1024, or 0 for all cores", "Worker threads (0 = all cores)"));
    o.back().recorded = nullptr;
    return o;
  }();
  return options;
}

}  // namespace emlt
