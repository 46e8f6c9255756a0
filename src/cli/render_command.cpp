#include <cmath>
#include <cstdlib>
#include <optional>
#include <cstdint>
#include <filesystem>
#include <future>
#include <fmt/core.h>

#include "cli/checkpoint_header.h"
#include "cli/commands.h"
#include "cli/fidelity.h"
#include "cli/mlt_report.h"
#include "cli/readable_range.h"
#include "cli/rank_agreement.h"
#include "cli/signals.h"
#include "emlt/mcmc/mlt_integrator.h"
#include "emlt/render/convergence_log.h"
#include "emlt/render/image_metrics.h"
#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/mcmc/pss_integrator.h"
#include "emlt/render/checkpoint_file.h"
#include "emlt/render/integrator.h"
#include "emlt/render/interruption.h"
#include "emlt/render/render_control.h"
#include "emlt/render/snapshot.h"
#include "emlt/scene/loader.h"

namespace emlt::cli {

namespace {

bool is_known_image_extension(const std::string& ext) {
  return ext == ".exr" || ext == ".pfm" || ext == ".png" || ext == ".hdr";
}

// Fails before a long render rather than after it.
void check_output_path(const std::string& path) {
  const std::filesystem::path p(path);
  if (!is_known_image_extension(p.extension().string()))
    throw file_error(path, "unknown output format (use .exr, .pfm, .png or .hdr)");
  const auto parent = p.parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent))
    throw file_error(path, "output directory does not exist");
}

}  // namespace

std::map<std::string, std::string> parse_defines(const std::vector<std::string>& defines) {
  std::map<std::string, std::string> result;
  for (const auto& d : defines) {
    const auto eq = d.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error("-D " + d + ": expected name=value");
    result[d.substr(0, eq)] = d.substr(eq + 1);
  }
  return result;
}

void add_render_options(CLI::App& command, RenderOptions& o) {
  RenderSettings& s = o.settings;
  command.add_option("scene", o.scene, "Scene file (.json or Mitsuba .xml)")->required();
  command.add_option("-o,--output", o.output, "Output image (.exr, .pfm, .png, .hdr)");
  std::string integrators;
  for (const std::string& name : integrator_names())
    integrators += (integrators.empty() ? "" : " | ") + name;
  command.add_option("--integrator", s.integrator, integrators);
  command.add_option("--spp", s.spp, "Samples per pixel")
      ->check(whole_number(1, kMaxSpp, "a whole number from 1 to 2^24 (about 16.8 million)"));
  command.add_option("--time", s.time_limit_s, "Time budget in seconds (renders until spent)")
      ->check(real_number(0.0, true, kMaxTimeSeconds,
                          "a positive number of seconds, at most 30 days"));
  command.add_option("--seed", s.seed, "Random seed (same seed, same image)")
      ->check(whole_number(0, INT64_MAX, "a whole number from 0 to 2^63 - 1"));
  command.add_option("--threads", s.threads, "Worker threads (0 = all cores)")
      ->check(whole_number(0, kMaxThreads, "1..1024, or 0 for all cores"));
  command.add_option("--width", s.width, "Image width in pixels")
      ->check(whole_number(1, 16384, "a whole number of pixels from 1 to 16384"));
  command.add_option("--height", s.height, "Image height in pixels")
      ->check(whole_number(1, 16384, "a whole number of pixels from 1 to 16384"));
  command.add_option("--max-depth", s.max_depth, "Longest path in segments (-1 = unlimited)")
      ->check(whole_number(-1, 100000, "a whole number from 0 to 100000, or -1 for unlimited"));
  command
      .add_option("--rr-depth", s.rr_depth,
                  "Segments before Russian roulette starts (bidirectional subpaths: one fewer, as "
                  "in Mitsuba)")
      ->check(whole_number(1, 100000, "a whole number from 1 to 100000"));
  command.add_option("--mis", o.mis, "MIS heuristic")->check(CLI::IsMember({"balance", "power"}));
  command.add_option("--direct-samples", s.direct_samples,
                     "Light and BSDF samples per direct-lighting estimate")
      ->check(whole_number(1, 1 << 16, "a whole number from 1 to 65536"));
  command.add_option("--direct-sampler", o.direct_point_set,
                     "Point set for direct lighting: independent | fibonacci")
      ->check(CLI::IsMember({"independent", "fibonacci"}));
  command.add_option("--bdpt-strategies", s.bdpt_strategies_dir,
                     "bdpt: also write each strategy's MIS-weighted image (s<s>_t<t>.exr) here");
  command.add_option("--mpp", s.mutations_per_pixel, "mlt: mutations per pixel")
      ->check(real_number(0.0, true, kMaxSpp,
                          "a positive number, at most 2^24 (about 16.8 million)"));
  command.add_option("--chains", s.chains, "mlt: independent chains (0 = from the budget)")
      ->check(whole_number(0, 1 << 20,
                           "1 to 2^20 (about a million), or 0 to choose from the budget"));
  command
      .add_option("--bootstrap", s.bootstrap_samples,
                  "mlt family: BDPT samples for b and the chains' seeds (default: 100000; for "
                  "mlt, gamlt and emlt then grown while the pool is worth fewer than two "
                  "candidates a chain)")
      ->check(whole_number(1, kMaxBootstrapSamples,
                           "a whole number from 1 to 2^24 (about 16.8 million)"));
  command.add_option("--bootstrap-seed", s.bootstrap_seed,
                     "mlt family: seed of the bootstrap and the chains' start paths, kept while "
                     "--seed varies the chains (default: --seed)")
      ->check(whole_number(0, INT64_MAX, "a whole number from 0 to 2^63 - 1"));
  command.add_option("--mutations", s.mutations,
                     "mlt/gamlt/emlt: strategy mix, e.g. bidir=3,lens=2, or a preset: mlt, gamlt, emlt, "
                     "emlt-ani, emlt-lin (default: the integrator's own)");
  command.add_option("--ensemble-size", s.ensemble_size,
                     "emlt: paths in each ensemble, |X| = |Y| (0 = 16384, fewer on small images)")
      ->check(whole_number(0, 1 << 17, "1 to 131072, or 0 for the default"));
  command.add_option("--ensemble-neighbours", s.ensemble_neighbours,
                     "emlt: guide paths of one step (M, default 8)")
      ->check(whole_number(1, 64, "a whole number from 1 to 64"));
  command.add_option("--ensemble-iterations", s.ensemble_iterations,
                     "emlt: steps per path between swaps (0 = W*H / (|X|+|Y|))")
      ->check(whole_number(0, 1 << 20,
                           "1 to 2^20 (about a million), or 0 for the image's pixels per path"));
  command.add_option("--ensemble-alpha", s.ensemble_alpha,
                     "emlt: fixed stretch scale alpha of the linear kernels (0 = adaptive, paper 3.4)")
      ->check(real_number(0.0, false, 100.0, "a number from 0 (adaptive) to 100"));
  command
      .add_option("--ensemble-similarity-length", s.ensemble_similarity_length,
                  "emlt: length (scene units) dividing distances in the path similarity (1 = "
                  "the paper's literal form; 0 = the scene's bounding radius / sqrt(3), which "
                  "is 1 on the paper's Cornell box)")
      ->check(real_number(0.0, false, HUGE_VAL, "a positive length, or 0 for the scene's own"));
  command.add_option("--ensemble-aniso-fallback", o.aniso_fallback,
                     "emlt: the anisotropic kernel's fallback when a fit is unusable: the paper's "
                     "vMF about the previous vertex's direction, or an isotropic Gaussian on the "
                     "tangent plane")
      ->check(CLI::IsMember({"vmf", "plane"}));
  command
      .add_option("--gamlt-cone", o.gamlt_cone,
                  "gamlt (the ga-* strategies): the occluder-free cones that set their step "
                  "ranges, by the exact hierarchy walk (exact), a cheap conservative bound "
                  "from a clearance field (field: narrower cones), or the exact walk memoised "
                  "for quantised segments (cells: the cone of the segment between the "
                  "endpoints' cell centres, shared by nearby states)")
      ->check(CLI::IsMember({"exact", "field", "cells"}));
  command
      .add_option("--gamlt-cone-cell", s.gamlt_cone_cells,
                  "gamlt with --gamlt-cone cells: the cells' size as a fraction of the "
                  "segment's length")
      ->check(real_number(0.0, true, 1.0, "a number above 0, at most 1"));
  command
      .add_option("--gamlt-acceptance", o.gamlt_acceptance,
                  "gamlt (the ga-* strategies): Metropolis-Hastings in one stage (full), or in "
                  "two (delayed: the ranges at the proposal, which need its cones, only for "
                  "proposals that pass a first stage without them; lower acceptance)")
      ->check(CLI::IsMember({"full", "delayed"}));
  command
      .add_option("--mlt-splat", o.mlt_splat,
                  "mlt/gamlt/emlt: what a step adds to the image: the proposal and the current "
                  "path weighted by the acceptance probability (expected), or the state after "
                  "the step (state)")
      ->check(CLI::IsMember({"expected", "state"}));
  command
      .add_option("--ensemble-aniso-covariance", o.ensemble_aniso_covariance,
                  "emlt: the anisotropic path perturbation's covariance: the paper's eq. 11 as "
                  "printed, or the reliability-weighted covariance times 0.05")
      ->check(CLI::IsMember({"printed", "weighted"}));
  command
      .add_option("--ensemble-aniso-scale", s.ensemble_aniso_scale,
                  "emlt: factor on the anisotropic path perturbation's fitted covariances "
                  "(0 = the form's own: 1 printed, 0.05 weighted)")
      ->check(real_number(0.0, false, 100.0, "a number from 0 (the default) to 100"));
  command
      .add_option("--ensemble-aniso-multiscale", s.ensemble_aniso_smallest_scale,
                  "emlt: the anisotropic path perturbation's Gaussians as scale mixtures over "
                  "[S, 1] of their fitted covariance's size, log-uniform (1 = the paper's single "
                  "Gaussian)")
      ->check(real_number(1e-4, false, 1.0, "a number from 0.0001 to 1"));
  command
      .add_option("--ensemble-guides", o.ensemble_guides,
                  "emlt: how a step's guides are chosen: by a counter over its path type's list "
                  "(the paper's 3.1.1), or the M paths of the type nearest the current path's "
                  "image point")
      ->check(CLI::IsMember({"counter", "nearby"}));
  command
      .add_option("--ensemble-alpha-from", o.ensemble_alpha_from,
                  "emlt: what the adaptive alpha (paper 3.4) is computed from: the image points "
                  "of the step's guides, or of the whole complementary ensemble")
      ->check(CLI::IsMember({"guides", "ensemble"}));
  command.add_option("--aniso-map", s.aniso_map_path,
                     "mlt/gamlt/emlt: write the predominant image-plane direction of the proposals "
                     "per pixel to this PNG (red horizontal, green vertical, yellow isotropic)");
  command.add_option("--direct", o.direct_mode,
                     "mlt: direct light rendered separately or by the chains")
      ->check(CLI::IsMember({"separate", "mlt"}));
  command.add_option("--direct-spp", s.direct_spp,
                     "mlt: samples of the separate direct image (default: the mutations per pixel)")
      ->check(whole_number(1, 1 << 20, "a whole number from 1 to 2^20 (about a million)"));
  command.add_option("--pss-tracer", o.pss_tracer,
                     "pssmlt: the sampler the primary samples drive: pt | bdpt")
      ->check(CLI::IsMember({"pt", "bdpt"}));
  command.add_option("--large-step", s.large_step_probability,
                     "pssmlt/mmlt: probability of a large step (default 0.3)")
      ->check(real_number(0.0, false, 1.0, "a probability from 0 to 1"));
  command.add_option("--pss-sigma", s.pss_sigma,
                     "pssmlt/mmlt: largest small-step perturbation of a coordinate (default 1/64)")
      ->check(real_number(0.0, true, 0.5, "a number above 0, at most 0.5"));
  command.add_option("--stats", s.stats_path, "mlt: write statistics as JSON to this file");
  command.add_option("--reference", o.reference, "Reference image for error metrics");
  command.add_option("--log", o.log,
                     "Convergence log (CSV) at power-of-two samples/mutations per pixel; needs --reference");
  command.add_option("--checkpoint", o.checkpoint,
                     "Save the render's whole state to this file every --checkpoint-interval "
                     "seconds, on Ctrl-C or SIGTERM, and when it finishes");
  command.add_option("--checkpoint-interval", o.checkpoint_interval,
                     "Seconds between checkpoints (default 600)")
      ->check(real_number(0.0, true, kMaxTimeSeconds,
                          "a positive number of seconds, at most 30 days"));
  command.add_option("--resume", o.resume,
                     "Continue the render saved in this checkpoint (same scene and settings; the "
                     "budget may grow); checkpoints go on into it unless --checkpoint says otherwise");
  command.add_option("-D", o.defines, "Scene parameter, name=value (repeatable)");
  command.add_flag("-q,--quiet", o.quiet, "No progress bar");
  command.add_flag("--strict", o.strict,
                   "Fail if the scene uses anything emlt approximates or cannot honour");
  command.add_flag("--bvh-only", o.bvh_only,
                   "Trace every ray through Embree's BVH, also on scenes of a few dozen triangles "
                   "that emlt otherwise tests one by one (for comparisons; the image differs "
                   "only by rounding)");
}

int run_render(const CLI::App& command, RenderOptions& o) {
  SceneDescription desc = load_scene_description(o.scene, parse_defines(o.defines));
  refuse_divergences_if_strict(desc, o.strict);

  // Scene file defaults first, then whatever the command line set explicitly.
  RenderSettings settings = desc.defaults;
  const RenderSettings& cli = o.settings;
  const auto given = [&](const char* name) { return command.count(name) > 0; };
  if (given("--integrator")) settings.integrator = cli.integrator;
  if (given("--spp")) settings.spp = cli.spp;
  if (given("--time")) {
    settings.time_limit_s = cli.time_limit_s;
    if (!given("--spp")) settings.spp = 0;  // the time budget alone decides
  }
  if (given("--seed")) settings.seed = cli.seed;
  if (given("--threads")) settings.threads = cli.threads;
  if (given("--max-depth")) settings.max_depth = cli.max_depth;
  if (given("--rr-depth")) settings.rr_depth = cli.rr_depth;
  if (given("--direct-samples")) settings.direct_samples = cli.direct_samples;
  if (given("--mpp")) settings.mutations_per_pixel = cli.mutations_per_pixel;
  if (given("--time") && !given("--mpp")) settings.mutations_per_pixel = 0.0;
  if (given("--chains")) settings.chains = cli.chains;
  if (given("--bootstrap")) {
    settings.bootstrap_samples = cli.bootstrap_samples;
    settings.bootstrap_grows = false;
  }
  if (given("--bootstrap-seed")) settings.bootstrap_seed = cli.bootstrap_seed;
  if (given("--mutations")) settings.mutations = cli.mutations;
  if (given("--direct")) settings.direct_separate = o.direct_mode == "separate";
  if (given("--direct-spp")) settings.direct_spp = cli.direct_spp;
  if (given("--stats")) settings.stats_path = cli.stats_path;
  if (given("--pss-tracer")) settings.pss_bdpt = o.pss_tracer == "bdpt";
  if (given("--large-step")) settings.large_step_probability = cli.large_step_probability;
  if (given("--pss-sigma")) settings.pss_sigma = cli.pss_sigma;
  if (given("--ensemble-size")) settings.ensemble_size = cli.ensemble_size;
  if (given("--ensemble-neighbours")) settings.ensemble_neighbours = cli.ensemble_neighbours;
  if (given("--ensemble-iterations")) settings.ensemble_iterations = cli.ensemble_iterations;
  if (given("--aniso-map")) settings.aniso_map_path = cli.aniso_map_path;
  if (given("--ensemble-alpha")) settings.ensemble_alpha = cli.ensemble_alpha;
  if (given("--ensemble-similarity-length"))
    settings.ensemble_similarity_length = cli.ensemble_similarity_length;
  if (given("--ensemble-aniso-fallback"))
    settings.ensemble_plane_fallback = o.aniso_fallback == "plane";
  if (given("--ensemble-aniso-scale")) settings.ensemble_aniso_scale = cli.ensemble_aniso_scale;
  if (given("--ensemble-aniso-multiscale"))
    settings.ensemble_aniso_smallest_scale = cli.ensemble_aniso_smallest_scale;
  if (given("--mlt-splat")) settings.mlt_expected_values = o.mlt_splat == "expected";
  if (given("--gamlt-cone")) {
    settings.gamlt_field_cone = o.gamlt_cone == "field";
    settings.gamlt_cone_cells = o.gamlt_cone != "cells"      ? 0.0
                                : given("--gamlt-cone-cell") ? cli.gamlt_cone_cells
                                                             : RenderSettings::kGamltConeCell;
  } else if (given("--gamlt-cone-cell") && settings.gamlt_cone_cells > 0.0) {
    settings.gamlt_cone_cells = cli.gamlt_cone_cells;
  }
  if (given("--gamlt-acceptance"))
    settings.gamlt_delayed_acceptance = o.gamlt_acceptance == "delayed";
  if (given("--ensemble-aniso-covariance"))
    settings.ensemble_aniso_weighted = o.ensemble_aniso_covariance == "weighted";
  if (given("--ensemble-guides")) settings.ensemble_nearby_guides = o.ensemble_guides == "nearby";
  if (given("--ensemble-alpha-from"))
    settings.ensemble_alpha_from_ensemble = o.ensemble_alpha_from == "ensemble";
  if (given("--bdpt-strategies")) settings.bdpt_strategies_dir = cli.bdpt_strategies_dir;
  settings.mis = o.mis == "balance" ? MisHeuristic::Balance : MisHeuristic::Power;
  settings.direct_point_set =
      o.direct_point_set == "fibonacci" ? DirectPointSet::Fibonacci : DirectPointSet::Independent;
  settings.progress = !o.quiet;
  if (given("--width")) desc.camera.width = cli.width;
  if (given("--height")) desc.camera.height = cli.height;

  if (o.output.empty()) o.output = std::filesystem::path(o.scene).stem().string() + ".exr";
  check_output_path(o.output);
  const auto integrator = make_integrator(settings.integrator);
  const bool path_space_mcmc = dynamic_cast<const MltIntegrator*>(integrator.get()) != nullptr;
  const bool mcmc =
      path_space_mcmc || dynamic_cast<const PssMltIntegrator*>(integrator.get()) != nullptr;
  if (!settings.aniso_map_path.empty()) {
    if (!path_space_mcmc) throw Error("--aniso-map needs an MCMC integrator (mlt, gamlt or emlt)");
    check_output_path(settings.aniso_map_path);
  }
  if (settings.integrator == "emlt" && given("--chains"))
    std::fprintf(stderr, "emlt: warning: --chains is ignored; the chains are the two ensembles (--ensemble-size)\n");
  if (!settings.stats_path.empty()) {
    const auto parent = std::filesystem::path(settings.stats_path).parent_path();
    if (!parent.empty() && !std::filesystem::is_directory(parent))
      throw file_error(settings.stats_path, "statistics directory does not exist");
  }

  if (!o.log.empty() && o.reference.empty()) throw Error("--log " + o.log + ": needs --reference");
  if (!o.log.empty()) {
    const auto parent = std::filesystem::path(o.log).parent_path();
    if (!parent.empty() && !std::filesystem::is_directory(parent))
      throw file_error(o.log, "log directory does not exist");
  }
  const Image reference = o.reference.empty() ? Image() : read_image(o.reference);

  // Checkpoints: what this run is, checked against a checkpoint to resume before anything
  // is rendered or written.
  const std::string checkpoint_path = o.checkpoint.empty() ? o.resume : o.checkpoint;
  if (!checkpoint_path.empty()) {
    const auto parent = std::filesystem::path(checkpoint_path).parent_path();
    if (!parent.empty() && !std::filesystem::is_directory(parent))
      throw file_error(checkpoint_path, "checkpoint directory does not exist");
    if (std::filesystem::path(checkpoint_path) == std::filesystem::path(o.output))
      throw file_error(checkpoint_path, "the checkpoint and the output image are the same file");
  }
  if (given("--checkpoint-interval") && checkpoint_path.empty())
    throw Error("--checkpoint-interval needs --checkpoint FILE (or --resume FILE)");
  // Only a render that checkpoints needs it: describing the run hashes every scene file
  // (a 1 M-triangle mesh: 5 % of a short render).
  const CheckpointHeader header_now = checkpoint_path.empty()
                                         ? CheckpointHeader{}
                                         : CheckpointHeader::describe(desc, settings, o.defines);
  // Under MPI each rank saves its own share: rank 0 into FILE, rank r into FILE.rank<r>.
  const auto rank_file = [](const std::string& path) {
    return cluster::rank() == 0 ? path : path + ".rank" + std::to_string(cluster::rank());
  };
  const std::string resume_path = o.resume.empty() ? "" : rank_file(o.resume);
  std::optional<CheckpointHeader> resumed_header;
  std::string resume_state;
  if (!o.resume.empty()) {
    checkpoint_file::Contents contents = checkpoint_file::read(resume_path);
    resumed_header = CheckpointHeader::decode(contents.header, resume_path);
    resumed_header->check_matches(header_now, resume_path);
    resume_state = std::move(contents.state);
  }

  const bool root = cluster::is_root();  // under MPI only rank 0 prints and writes
  const auto scene =
      Scene::build(std::move(desc), SceneBuildOptions{.direct_triangles = !o.bvh_only});
  for (const auto& w : scene->warnings())
    if (root) std::fprintf(stderr, "emlt: warning: %s\n", w.c_str());
  if (const std::string summary = divergence_summary(scene->description()); !summary.empty() && root)
    std::fprintf(stderr, "emlt: warning: %s\n", summary.c_str());
  std::vector<uint8_t> sees_emitter;
  if (!o.reference.empty()) {
    if (reference.width != scene->camera().width() || reference.height != scene->camera().height())
      throw file_error(o.reference, "reference is " + std::to_string(reference.width) + "x" +
                                        std::to_string(reference.height) + " but the render is " +
                                        std::to_string(scene->camera().width()) + "x" +
                                        std::to_string(scene->camera().height()));
    sees_emitter = directly_visible_emitters(*scene);
  }
  std::unique_ptr<ConvergenceLog> log;
  // The other ranks take part in every snapshot (the image is merged on rank 0) and keep
  // nothing of it.
  struct NoSnapshots final : SnapshotSink {
    void snapshot(double, double, const Image&, const std::vector<StrategyAcceptance>&) override {}
  } no_snapshots;
  if (!o.log.empty()) {
    log = std::make_unique<ConvergenceLog>(o.log, reference, sees_emitter, scene->camera().width(),
                                           scene->camera().height());
    settings.snapshots = root ? static_cast<SnapshotSink*>(log.get()) : &no_snapshots;
    if (resumed_header) log->restore(resumed_header->log_header, resumed_header->log_rows);
  }
  if (!root) settings.progress = false;
  setup_succeeded();  // every rank is ready (rank_agreement.h)

  RenderControl control(checkpoint_path.empty() ? "" : rank_file(checkpoint_path),
                        o.checkpoint_interval, [&] {
    CheckpointHeader header = header_now;
    if (log) {
      header.log_header = log->header();
      header.log_rows = log->row_texts();
    }
    return header.encode();
  });
  control.set_resume_state(std::move(resume_state));
  settings.control = &control;
  // Test hook: stop as if by Ctrl-C after this many samples or mutations (tests/e2e).
  if (const char* units = std::getenv("EMLT_STOP_AFTER"))
    interruption::stop_after(std::strtoull(units, nullptr, 10));
  handle_stop_signals();

  ProgressReporter progress(settings.progress);
  RenderResult result;
  try {
    result = integrator->render(*scene, settings, progress);
  } catch (const StateError& e) {
    throw file_error(resume_path, std::string("cannot resume: ") + e.what());
  }
  if (!root) return result.interrupted ? exit_status_for_stop() : 0;

  // The PNG preview is written beside the image, at once: each is one thread's compression.
  std::string outputs = o.output;
  std::future<void> preview_written;
  if (std::filesystem::path(o.output).extension().string() != ".png") {
    const std::string preview = preview_path_for(o.output);
    preview_written = std::async(std::launch::async, [&image = result.image, preview] {
      write_image(preview, image);
    });
    outputs += " + " + preview;
  }
  write_image(o.output, result.image);
  if (preview_written.valid()) preview_written.get();
  if (const auto* mlt = dynamic_cast<const MltIntegrator*>(integrator.get()))
    report_mlt_statistics(settings.integrator, mlt->statistics(), settings.stats_path);
  if (const auto* pss = dynamic_cast<const PssMltIntegrator*>(integrator.get()))
    report_mlt_statistics(settings.integrator, pss->statistics(), settings.stats_path);
  if (!o.reference.empty()) {
    const ImageMetrics m = compare_images(reference, result.image, std::nullopt, &sees_emitter);
    std::fprintf(stderr, "against %s: mse %.6g, relmse %.6g, mse without visible emitters %.6g, mean ratio %.5f\n",
                 o.reference.c_str(), m.mse, m.rel_mse, m.mse_no_emitter, m.mean_ratio);
  }
  if (result.invalid_samples > 0)
    std::fprintf(stderr, "emlt: warning: %llu NaN/Inf samples were dropped\n",
                 static_cast<unsigned long long>(result.invalid_samples));
  if (result.interrupted) {
    const char* unit = mcmc ? "mutations" : "samples";
    std::string done = fmt::format("{:.4g} {} per pixel", result.per_pixel, unit);
    if (!result.stopped_in.empty()) done = "in " + result.stopped_in + ", before the chains began";
    std::string saved;
    if (control.checkpoints_written() > 0)
      saved = fmt::format("; state saved in {} (continue with --resume {})", checkpoint_path,
                          checkpoint_path);
    fmt::print("{}: stopped by {} after {:.2f} s, {} -> {}{}\n", integrator->name(),
               stop_signal_name(), result.seconds, done, outputs, saved);
    return exit_status_for_stop();
  }
  const double rate = result.seconds > 0.0 ? double(result.samples) / result.seconds : 0.0;
  // An MCMC render's work is counted in mutations (its samples_per_pixel is the mutations per
  // pixel, rounded), not in camera samples.
  if (mcmc)
    fmt::print("{}: {}x{}, {:.4g} mutations per pixel, {:.2f} s, {:.3f} M mutations/s -> {}\n",
               integrator->name(), result.image.width, result.image.height,
               double(result.samples) / (double(result.image.width) * result.image.height),
               result.seconds, rate * 1e-6, outputs);
  else
    fmt::print("{}: {}x{}, {} spp, {:.2f} s, {:.3f} M samples/s -> {}\n", integrator->name(),
               result.image.width, result.image.height, result.samples_per_pixel, result.seconds,
               rate * 1e-6, outputs);
  return 0;
}

}  // namespace emlt::cli
