#include "emlt/integrators/mlt/mlt_options.h"

#include <cmath>
#include <cstdint>
#include <string>

namespace emlt {

namespace {

// A count whose 0 means "chosen from the budget", as the checkpoint records it.
std::string from_budget(int value) {
  return value > 0 ? recorded_number(int64_t(value)) : "(from the budget)";
}

// The integrators whose --mutations may name any path-space strategy (the ga-* ones read the
// gamlt options, the emlt-* ones the ensemble's).
bool path_space_family(const RenderSettings& s) {
  return s.integrator == "mlt" || s.integrator == "gamlt" || s.integrator == "emlt" ||
         s.integrator == "memlt";
}

}  // namespace

const std::vector<RenderOption>& mlt_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> o;
    // The budget may grow on a resume.
    o.push_back(real_option("--mpp", &RenderSettings::mutations_per_pixel, 0.0, true, kMaxSpp,
                            "a positive number, at most 2^24 (about 16.8 million)",
                            "mlt: mutations per pixel"));
    o.back().recorded = nullptr;
    o.push_back(whole_option("--chains", &RenderSettings::chains, 0, 1 << 20,
                             "1 to 2^20 (about a million), or 0 to choose from the budget",
                             "mlt: independent chains (0 = from the budget: one per 64 "
                             "mutations, for memlt one per 4,096, 16 to 16,384)"));
    o.back().recorded = [](const RenderSettings& s) { return from_budget(s.chains); };
    o.push_back(whole_option("--bootstrap", &RenderSettings::bootstrap_samples, 1,
                             kMaxBootstrapSamples,
                             "a whole number from 1 to 2^24 (about 16.8 million)",
                             "mlt family: BDPT samples for b and the chains' seeds (default: "
                             "100000; for mlt, gamlt and emlt then grown while the pool is worth "
                             "fewer than two candidates a chain)"));
    // A pool of the size given is kept as it is.
    o.back().assign = [](RenderSettings& s, const std::string& text) {
      s.bootstrap_samples = std::stoi(text);
      s.bootstrap_grows = false;
    };
    o.back().recorded = [](const RenderSettings& s) {
      // Only the path-space MLT family grows its pool (mlt_integrator.cpp).
      const bool grows = s.bootstrap_grows && path_space_family(s);
      return recorded_number(int64_t(s.bootstrap_samples)) + (grows ? " (grown as needed)" : "");
    };
    RenderOption start;
    start.flag = "--bootstrap-seed";
    start.help =
        "mlt family: seed of the bootstrap and the chains' start paths, kept while --seed varies "
        "the chains (default: --seed)";
    start.values = {OptionValues::Kind::Whole,          0.0, double(INT64_MAX), false, {},
                    "a whole number from 0 to 2^63 - 1"};
    start.assign = [](RenderSettings& s, const std::string& text) {
      s.bootstrap_seed = std::stoull(text);
    };
    start.recorded = [](const RenderSettings& s) {
      return s.bootstrap_seed ? recorded_number(*s.bootstrap_seed) : std::string("(--seed)");
    };
    o.push_back(start);
    o.push_back(real_option("--normalisation-rate", &RenderSettings::normalisation_rate, 0.0,
                            false, 64.0, "a number from 0 to 64",
                            "mlt/gamlt/emlt: bootstrap samples per mutation drawn beside the "
                            "chains, so that b (the image's scale) keeps converging (default "
                            "1/64, about a tenth of the time; 0: the bootstrap's b alone)"));
    RenderOption mix;
    mix.flag = "--mutations";
    mix.help =
        "mlt/gamlt/emlt/memlt: strategy mix, e.g. bidir=3,lens=2, or a preset: mlt, gamlt, "
        "emlt, emlt-ani, emlt-lin, memlt (default: the integrator's own)";
    mix.values = {OptionValues::Kind::Text, 0, 0, false, {}, "a strategy mix"};
    mix.assign = [](RenderSettings& s, const std::string& text) { s.mutations = text; };
    mix.recorded = [](const RenderSettings& s) {
      return s.mutations.empty() ? std::string("(the integrator's own)") : s.mutations;
    };
    o.push_back(mix);
    o.push_back(real_option("--manifold-lambda", &RenderSettings::manifold_lambda, 0.0, true,
                            1e6, "a positive number, at most a million",
                            "the manifold perturbation (memlt, or manifold in any mix): its "
                            "direction lobe's peak is lambda^2 times the start vertex's own "
                            "density; larger is smaller steps (Mitsuba's probFactor/lambda, "
                            "default 50)"));
    // The path-space strategies' (ERPT's chains take them too).
    o.back().applies = [](const RenderSettings& s) {
      return path_space_family(s) || s.integrator == "erpt";
    };
    o.push_back(real_option("--manifold-angle-change", &RenderSettings::manifold_angle_change,
                            0.0, false, 90.0, "a number of degrees from 0 to 90",
                            "the manifold perturbation's offset manifolds: the typical turn of "
                            "a rough vertex's microfacet normal per move, which sets how often "
                            "rough vertices are crossed as specular (Mitsuba's "
                            "avgAngleChangeSurface; default 1; 0: never)"));
    o.back().applies = [](const RenderSettings& s) {
      return path_space_family(s) || s.integrator == "erpt";
    };
    o.push_back(switch_option("--direct", &RenderSettings::direct_separate, "mlt", "separate",
                              "mlt: direct light rendered separately or by the chains"));
    o.push_back(whole_option("--direct-spp", &RenderSettings::direct_spp, 1, 1 << 20,
                             "a whole number from 1 to 2^20 (about a million)",
                             "mlt: samples of the separate direct image (default: the mutations "
                             "per pixel)"));
    o.back().recorded = [](const RenderSettings& s) { return from_budget(s.direct_spp); };
    o.push_back(switch_option("--mlt-splat", &RenderSettings::mlt_expected_values, "state",
                              "expected",
                              "mlt/gamlt/emlt: what a step adds to the image: the proposal and "
                              "the current path weighted by the acceptance probability "
                              "(expected), or the state after the step (state)"));
    o.push_back(path_option("--stats", &RenderSettings::stats_path,
                            "mlt: write statistics as JSON to this file"));
    RenderOption map = path_option("--aniso-map", &RenderSettings::aniso_map_path,
                                   "mlt/gamlt/emlt: write the predominant image-plane direction "
                                   "of the proposals per pixel to this PNG (red horizontal, "
                                   "green vertical, yellow isotropic)");
    // Whether the directions were being recorded, not where they go.
    map.recorded = [](const RenderSettings& s) {
      return std::string(s.aniso_map_path.empty() ? "(none)" : "(a file)");
    };
    o.push_back(map);
    return o;
  }();
  return options;
}

const std::vector<RenderOption>& gamlt_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> o;
    RenderOption cone;
    cone.flag = "--gamlt-cone";
    cone.help =
        "gamlt (the ga-* strategies): the occluder-free cones that set their step ranges, by the "
        "exact walk memoised for quantised segments (cells, the default: the cone of the segment "
        "between the endpoints' cell centres, shared by nearby states), the exact hierarchy walk "
        "for each segment (exact), or a cheap conservative bound from a clearance field (field: "
        "narrower cones)";
    cone.values = {OptionValues::Kind::Word, 0, 0, false, {"cells", "exact", "field"},
                   "cells, exact or field"};
    cone.assign = [](RenderSettings& s, const std::string& text) {
      s.gamlt_field_cone = text == "field";
      // Cells keep a size --gamlt-cone-cell gave; otherwise they take their own.
      s.gamlt_cone_cells = text != "cells"            ? 0.0
                           : s.gamlt_cone_cells > 0.0 ? s.gamlt_cone_cells
                                                      : RenderSettings::kGamltConeCell;
    };
    cone.recorded = [](const RenderSettings& s) {
      return s.gamlt_field_cone         ? std::string("field")
             : s.gamlt_cone_cells > 0.0 ? "cells (" + recorded_number(s.gamlt_cone_cells) + ")"
                                        : std::string("exact");
    };
    o.push_back(cone);
    // The size is part of --gamlt-cone's record; alone (without cells) it changes nothing.
    RenderOption cell = real_option("--gamlt-cone-cell", &RenderSettings::gamlt_cone_cells, 0.0,
                                    true, 1.0, "a number above 0, at most 1",
                                    "gamlt with --gamlt-cone cells: the cells' size as a fraction "
                                    "of the segment's length (default 1/2)");
    cell.assign = [](RenderSettings& s, const std::string& text) {
      if (s.gamlt_field_cone || s.gamlt_cone_cells == 0.0) return;
      s.gamlt_cone_cells = std::stod(text);
    };
    cell.recorded = nullptr;
    o.push_back(cell);
    o.push_back(switch_option(
        "--gamlt-acceptance", &RenderSettings::gamlt_delayed_acceptance, "full", "delayed",
        "gamlt (the ga-* strategies): Metropolis-Hastings in one stage (full), or in two "
        "(delayed: the ranges at the proposal, which need its cones, only for proposals that "
        "pass a first stage without them; lower acceptance)"));
    apply_only_where(o, path_space_family);
    return o;
  }();
  return options;
}

const std::vector<RenderOption>& ensemble_options() {
  static const std::vector<RenderOption> options = [] {
    std::vector<RenderOption> o;
    o.push_back(whole_option("--ensemble-size", &RenderSettings::ensemble_size, 0, 1 << 17,
                             "1 to 131072, or 0 for the default",
                             "emlt: paths in each ensemble, |X| = |Y| (0 = 16384, fewer on small "
                             "images)"));
    o.push_back(whole_option("--ensemble-neighbours", &RenderSettings::ensemble_neighbours, 1, 64,
                             "a whole number from 1 to 64",
                             "emlt: guide paths of one step (M, default 8)"));
    o.push_back(whole_option("--ensemble-iterations", &RenderSettings::ensemble_iterations, 0,
                             1 << 20,
                             "1 to 2^20 (about a million), or 0 for the image's pixels per path",
                             "emlt: steps per path between swaps (0 = W*H / (|X|+|Y|))"));
    o.push_back(real_option("--ensemble-alpha", &RenderSettings::ensemble_alpha, 0.0, false, 100.0,
                            "a number from 0 (adaptive) to 100",
                            "emlt: fixed stretch scale alpha of the linear kernels (0 = adaptive, "
                            "paper 3.4)"));
    o.push_back(real_option("--ensemble-similarity-length",
                            &RenderSettings::ensemble_similarity_length, 0.0, false, HUGE_VAL,
                            "a positive length, or 0 for the scene's own",
                            "emlt: length (scene units) dividing distances in the path similarity "
                            "(1 = the paper's literal form; 0 = the scene's bounding radius / "
                            "sqrt(3), which is 1 on the paper's Cornell box)"));
    o.push_back(switch_option("--ensemble-aniso-fallback", &RenderSettings::ensemble_plane_fallback,
                              "vmf", "plane",
                              "emlt: the anisotropic kernel's fallback when a fit is unusable: "
                              "the paper's vMF about the previous vertex's direction, or an "
                              "isotropic Gaussian on the tangent plane"));
    o.push_back(real_option("--ensemble-aniso-scale", &RenderSettings::ensemble_aniso_scale, 0.0,
                            false, 100.0, "a number from 0 (the default) to 100",
                            "emlt: factor on the anisotropic path perturbation's fitted "
                            "covariances (0 = the form's own: 1 printed, 0.05 weighted)"));
    o.push_back(real_option("--ensemble-aniso-multiscale",
                            &RenderSettings::ensemble_aniso_smallest_scale, 1e-4, false, 1.0,
                            "a number from 0.0001 to 1",
                            "emlt: the anisotropic path perturbation's Gaussians as scale "
                            "mixtures over [S, 1] of their fitted covariance's size, log-uniform "
                            "(1 = the paper's single Gaussian)"));
    o.push_back(switch_option("--ensemble-aniso-covariance",
                              &RenderSettings::ensemble_aniso_weighted, "printed", "weighted",
                              "emlt: the anisotropic path perturbation's covariance: the paper's "
                              "eq. 11 as printed, or the reliability-weighted covariance times "
                              "0.05"));
    o.push_back(switch_option("--ensemble-guides", &RenderSettings::ensemble_nearby_guides,
                              "counter", "nearby",
                              "emlt: how a step's guides are chosen: by a counter over its path "
                              "type's list (the paper's 3.1.1), or the M paths of the type "
                              "nearest the current path's image point"));
    o.push_back(switch_option("--ensemble-alpha-from",
                              &RenderSettings::ensemble_alpha_from_ensemble, "guides", "ensemble",
                              "emlt: what the adaptive alpha (paper 3.4) is computed from: the "
                              "image points of the step's guides, or of the whole complementary "
                              "ensemble"));
    apply_only_where(o, path_space_family);
    // ERPT's chains take the same strategies, and its chain counts the bootstrap's b; its
    // direct light is left to BDPT as the family's is to the direct pass.
    for (RenderOption& option : o)
      if (option.flag == "--mutations" || option.flag == "--bootstrap" ||
          option.flag == "--bootstrap-seed" || option.flag == "--direct")
        option.applies = [](const RenderSettings& s) {
          return path_space_family(s) || s.integrator == "erpt";
        };
    return o;
  }();
  return options;
}

}  // namespace emlt
