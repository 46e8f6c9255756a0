#include <fmt/core.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <optional>

#include "cli/checkpoint_header.h"
#include "cli/commands.h"
#include "cli/fidelity.h"
#include "cli/mlt_report.h"
#include "cli/rank_agreement.h"
#include "cli/readable_range.h"
#include "cli/signals.h"
#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/image/image_metrics.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/integrators/pss/pss_integrator.h"
#include "emlt/integrators/registry.h"
#include "emlt/run/checkpoint_file.h"
#include "emlt/run/convergence_log.h"
#include "emlt/run/integrator.h"
#include "emlt/run/render_control.h"
#include "emlt/run/scene_settings.h"
#include "emlt/run/snapshot.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/visible_emitters.h"
#include "emlt/settings/render_option.h"

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

// A validator that refuses what the option does not take, in its own words.
CLI::Validator validator_for(const OptionValues& values) {
  switch (values.kind) {
    case OptionValues::Kind::Whole: {
      const auto whole = [](double v) {
        return v >= 9.2e18 ? INT64_MAX : v <= -9.2e18 ? INT64_MIN : int64_t(v);
      };
      return whole_number(whole(values.low), whole(values.high), values.takes);
    }
    case OptionValues::Kind::Real:
      return real_number(values.low, values.low_open, values.high, values.takes);
    case OptionValues::Kind::Word:
      return CLI::IsMember(values.words);
    case OptionValues::Kind::Text:
      break;
  }
  return CLI::Validator();
}

void add_render_options(CLI::App& command, RenderOptions& o) {
  command.add_option("scene", o.scene, "Scene file (.json or Mitsuba .xml)")->required();
  command.add_option("-o,--output", o.output, "Output image (.exr, .pfm, .png, .hdr)");
  std::string integrators;
  for (const std::string& name : integrator_names())
    integrators += (integrators.empty() ? "" : " | ") + name;
  command.add_option("--integrator", o.integrator, integrators);
  command.add_option("--width", o.width, "Image width in pixels")
      ->check(whole_number(1, 16384, "a whole number of pixels from 1 to 16384"));
  command.add_option("--height", o.height, "Image height in pixels")
      ->check(whole_number(1, 16384, "a whole number of pixels from 1 to 16384"));
  // Every option an integrator or the run loop declares.
  for (const RenderOption& option : render_options()) {
    CLI::Option* added = command.add_option(option.flag, o.option_text[option.flag], option.help);
    if (option.values.kind != OptionValues::Kind::Text) added->check(validator_for(option.values));
  }
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

  // The engine's defaults, then what the scene file says, then what the command line says.
  RenderSettings settings = settings_for(desc.render);
  apply_integrator_options(desc.render, settings);
  const auto given = [&](const char* name) { return command.count(name) > 0; };
  if (given("--integrator")) settings.integrator = o.integrator;
  for (const RenderOption& option : render_options())
    if (command.count(option.flag) > 0) option.set(settings, o.option_text.at(option.flag));
  // A time budget alone decides how much is rendered, unless a sample count caps it.
  if (given("--time") && !given("--spp")) settings.spp = 0;
  if (given("--time") && !given("--mpp")) settings.mutations_per_pixel = 0.0;
  settings.progress = !o.quiet;
  if (given("--width")) desc.camera.width = o.width;
  if (given("--height")) desc.camera.height = o.height;
  // A file's crop window is a part of the film it gives: another film size renders it whole.
  if (given("--width") || given("--height")) desc.camera.crop_width = desc.camera.crop_height = 0;

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
  // A collimated beam lights the scene only through paths that light tracing makes: light
  // sampling (the path tracer's, the direct integrator's, the MCMC integrators' separate
  // direct image) never finds it.
  if (!desc.collimated_lights.empty()) {
    if (settings.integrator == "pt" || settings.integrator == "direct")
      std::fprintf(stderr,
                   "emlt: warning: %s cannot sample a collimated beam (nor can Mitsuba's path "
                   "tracer): its light is missing; bdpt, ptracer and the MCMC integrators render it\n",
                   settings.integrator.c_str());
    else if (mcmc && settings.direct_separate && given("--direct"))
      std::fprintf(stderr, "emlt: warning: with --direct separate the collimated beam's direct "
                           "light is missing (light sampling cannot find it); --direct mlt "
                           "renders it\n");
    else if (mcmc && settings.direct_separate) {
      settings.direct_separate = false;
      std::fprintf(stderr, "emlt: note: a collimated beam: the direct light is rendered by the "
                           "chains (--direct mlt), as light sampling cannot find the beam\n");
    }
  }
  if (settings.integrator == "emlt" && given("--chains"))
    std::fprintf(stderr, "emlt: warning: --chains is ignored; the chains are the two ensembles (--ensemble-size)\n");
  if (given("--gamlt-cone-cell") && settings.gamlt_cone_cells == 0.0)
    std::fprintf(stderr,
                 "emlt: warning: --gamlt-cone-cell is ignored without --gamlt-cone cells\n");
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
  uint32_t resume_format = checkpoint_file::kVersion;
  if (!o.resume.empty()) {
    checkpoint_file::Contents contents = checkpoint_file::read(resume_path);
    resumed_header = CheckpointHeader::decode(contents.header, resume_path);
    resumed_header->check_matches(header_now, resume_path);
    resume_state = std::move(contents.state);
    resume_format = contents.version;
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
  control.set_resume_state(std::move(resume_state), resume_format);
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
  if (const auto* chains = dynamic_cast<const ChainStatisticsSource*>(integrator.get()))
    report_mlt_statistics(settings.integrator, chains->chain_statistics(), settings.stats_path);
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
