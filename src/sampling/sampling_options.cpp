#include "emlt/sampling/sampling_options.h"

#include <cstdlib>

#include "emlt/settings/scene_options.h"

namespace emlt {

const std::vector<RenderOption>& sampling_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> o;
    for (const char* flag : {"--max-depth", "--rr-depth", "--hide-emitters"})
      o.push_back(scene_file_option(flag).option);
    RenderOption mis;
    mis.flag = "--mis";
    mis.help = "MIS heuristic: balance | power | max | second-order";
    mis.values = {OptionValues::Kind::Word,
                  0,
                  0,
                  false,
                  {"balance", "power", "max", "second-order"},
                  "balance, power, max or second-order"};
    mis.assign = [](RenderSettings& s, const std::string& text) {
      s.mis = text == "balance"        ? MisHeuristic::Balance
              : text == "max"          ? MisHeuristic::Max
              : text == "second-order" ? MisHeuristic::SecondOrder
                                       : MisHeuristic::Power;
    };
    mis.recorded = [](const RenderSettings& s) { return std::string(to_string(s.mis)); };
    o.push_back(mis);
    o.push_back(whole_option("--direct-samples", &RenderSettings::direct_samples, 1, 1 << 16,
                             "a whole number from 1 to 65536",
                             "Light and BSDF samples per direct-lighting estimate"));
    RenderOption points;
    points.flag = "--direct-sampler";
    points.help =
        "Direct lighting: independent | fibonacci | sobol | larcher-pillichshammer | "
        "blue-noise (randomised point sets, unbiased) | bmc (Bayesian Monte Carlo) | adaptive "
        "(Szecsi et al.); bmc and adaptive are biased, direct only";
    points.values = {OptionValues::Kind::Word,
                     0,
                     0,
                     false,
                     {"independent", "fibonacci", "sobol", "larcher-pillichshammer", "blue-noise",
                      "bmc", "adaptive"},
                     "independent, fibonacci, sobol, larcher-pillichshammer, blue-noise, bmc or "
                     "adaptive"};
    points.assign = [](RenderSettings& s, const std::string& text) {
      s.direct_point_set = direct_point_set_from_name(text);
    };
    points.recorded = [](const RenderSettings& s) {
      return std::string(direct_point_set_name(s.direct_point_set));
    };
    o.push_back(points);
    for (RenderOption& option : bmc_options()) o.push_back(std::move(option));
    RenderOption env;
    env.flag = "--env-sampler";
    env.help = "How direct lighting samples the environment: latlong | cube-balanced";
    env.values = {OptionValues::Kind::Word,  0, 0, false, {"latlong", "cube-balanced"},
                  "latlong or cube-balanced"};
    env.assign = [](RenderSettings& s, const std::string& text) {
      s.env_sampler = text == "cube-balanced" ? EnvSampler::CubeBalanced : EnvSampler::LatLong;
    };
    env.recorded = [](const RenderSettings& s) {
      return std::string(s.env_sampler == EnvSampler::CubeBalanced ? "cube-balanced" : "latlong");
    };
    // Recorded in a checkpoint only when it is not the default, so that checkpoints written
    // before the option existed still resume.
    env.applies = [](const RenderSettings& s) { return s.env_sampler != EnvSampler::LatLong; };
    o.push_back(env);
    RenderOption balance;
    balance.flag = "--env-face-balance";
    balance.help =
        "cube-balanced: how faces share samples: receiver (Lu's Eq. 3.4) | uniform | mass";
    balance.values = {OptionValues::Kind::Word,   0, 0, false, {"receiver", "uniform", "mass"},
                      "receiver, uniform or mass"};
    balance.assign = [](RenderSettings& s, const std::string& text) {
      s.env_face_balance = text == "uniform" ? CubeFaceBalance::Uniform
                           : text == "mass"  ? CubeFaceBalance::Mass
                                             : CubeFaceBalance::Receiver;
    };
    balance.recorded = [](const RenderSettings& s) {
      return std::string(s.env_face_balance == CubeFaceBalance::Uniform ? "uniform"
                         : s.env_face_balance == CubeFaceBalance::Mass  ? "mass"
                                                                        : "receiver");
    };
    balance.applies = [](const RenderSettings& s) {
      return s.env_sampler == EnvSampler::CubeBalanced;
    };
    o.push_back(balance);
    RenderOption counts;
    counts.flag = "--env-face-counts";
    counts.help =
        "cube-balanced, direct: light samples per face: fractional (Lu's Eqs. 3.5-3.6, "
        "expected counts) | sampled (a face chosen per sample; pt and the chains always)";
    counts.values = {OptionValues::Kind::Word, 0, 0, false, {"fractional", "sampled"},
                     "fractional or sampled"};
    counts.assign = [](RenderSettings& s, const std::string& text) {
      s.env_face_counts = text == "sampled" ? EnvFaceCounts::Sampled : EnvFaceCounts::Fractional;
    };
    counts.recorded = [](const RenderSettings& s) {
      return std::string(s.env_face_counts == EnvFaceCounts::Sampled ? "sampled" : "fractional");
    };
    counts.applies = balance.applies;
    o.push_back(counts);
    RenderOption resolution =
        whole_option("--env-cube-resolution", &RenderSettings::env_cube_resolution, 0, 2048,
                     "a whole number from 0 to 2048",
                     "cube-balanced: texels per cube face edge (0: a quarter of the map's width)");
    resolution.applies = balance.applies;
    o.push_back(resolution);

    // --mis second-order's split (sampling/mixture_direct_estimator.h); they change nothing
    // under the other heuristics, so only second-order renders record them.
    std::vector<RenderOption> split;
    RenderOption alpha;
    alpha.flag = "--mis-alpha";
    alpha.help = "Fixed share of direct-lighting directions drawn from the lights (second-order)";
    alpha.values = {OptionValues::Kind::Real, 0.0, 1.0, false, {}, "a number from 0 to 1"};
    alpha.assign = [](RenderSettings& s, const std::string& text) {
      s.mis_alpha = std::strtod(text.c_str(), nullptr);
    };
    alpha.recorded = [](const RenderSettings& s) {
      return s.mis_alpha < 0.0 ? std::string("estimated") : recorded_number(s.mis_alpha);
    };
    split.push_back(alpha);
    RenderOption estimate;
    estimate.flag = "--mis-alpha-estimate";
    estimate.help = "How second-order estimates its split: online | preprocessed";
    estimate.values = {OptionValues::Kind::Word, 0, 0, false, {"online", "preprocessed"},
                       "online or preprocessed"};
    estimate.assign = [](RenderSettings& s, const std::string& text) {
      s.mis_alpha_estimate =
          text == "preprocessed" ? MisAlphaEstimate::Preprocessed : MisAlphaEstimate::Online;
    };
    estimate.recorded = [](const RenderSettings& s) {
      return std::string(s.mis_alpha_estimate == MisAlphaEstimate::Preprocessed ? "preprocessed"
                                                                                : "online");
    };
    split.push_back(estimate);
    split.push_back(real_option("--mis-alpha-pilot", &RenderSettings::mis_alpha_pilot, 0.0, true,
                                1.0, "a number above 0, at most 1",
                                "Online: share of a point's directions spent estimating alpha"));
    split.push_back(whole_option("--mis-alpha-samples", &RenderSettings::mis_alpha_samples, 2,
                                 1 << 20, "a whole number from 2 to 1048576",
                                 "Preprocessed: pilot directions per pixel"));
    split.push_back(real_option("--mis-alpha-clamp", &RenderSettings::mis_alpha_clamp, 0.0, false,
                                0.5, "a number from 0 to 0.5",
                                "The estimated alpha is kept within [c, 1 - c]"));
    apply_only_where(split,
                     [](const RenderSettings& s) { return s.mis == MisHeuristic::SecondOrder; });
    o.insert(o.end(), split.begin(), split.end());
    return o;
  }();
  return options;
}

}  // namespace emlt
