#include "cli/render_job.h"

#include <cstdio>
#include <filesystem>

#include "cli/checkpoint_header.h"
#include "cli/commands.h"
#include "cli/fidelity.h"
#include "cli/rank_agreement.h"
#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/integrators/pss/pss_integrator.h"
#include "emlt/integrators/registry.h"
#include "emlt/run/checkpoint_file.h"
#include "emlt/run/convergence_log.h"
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

void check_directory_of(const std::string& path, const char* what) {
  const auto parent = std::filesystem::path(path).parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent))
    throw file_error(path, std::string(what) + " directory does not exist");
}

// The other ranks take part in every snapshot (the image is merged on rank 0) and keep
// nothing of it.
struct NoSnapshots final : SnapshotSink {
  void snapshot(double, double, const Image&, const std::vector<StrategyAcceptance>&) override {}
};

}  // namespace

struct RenderJob::Run {
  CheckpointHeader header_now;
  std::unique_ptr<ConvergenceLog> log;
  NoSnapshots no_snapshots;
  std::unique_ptr<RenderControl> control;
};

RenderJob::RenderJob(RenderRequest request, const Warn& warn)
    : request_(std::move(request)), run_(std::make_unique<Run>()) {
  const RenderRequest& r = request_;
  SceneDescription desc = load_scene_description(r.scene, parse_defines(r.defines));
  refuse_divergences_if_strict(desc, r.strict);

  // The engine's defaults, then what the scene file says, then what the request says.
  settings_ = settings_for(desc.render);
  apply_integrator_options(desc.render, settings_);
  const auto given = [&](const char* flag) { return r.options.count(flag) > 0; };
  if (r.integrator) settings_.integrator = *r.integrator;
  for (const RenderOption& option : render_options())
    if (const auto text = r.options.find(option.flag); text != r.options.end())
      option.set(settings_, text->second);
  // A time budget alone decides how much is rendered, unless a sample count caps it.
  if (given("--time") && !given("--spp")) settings_.spp = 0;
  if (given("--time") && !given("--mpp")) settings_.mutations_per_pixel = 0.0;
  settings_.progress = r.progress;
  if (r.width) desc.camera.width = *r.width;
  if (r.height) desc.camera.height = *r.height;
  // A file's crop window is a part of the film it gives: another film size renders it whole.
  if (r.width || r.height) desc.camera.crop_width = desc.camera.crop_height = 0;

  if (!r.output.empty()) check_output_path(r.output);
  integrator_ = make_integrator(settings_.integrator);
  const bool path_space_mcmc = dynamic_cast<const MltIntegrator*>(integrator_.get()) != nullptr;
  mcmc_ = path_space_mcmc || dynamic_cast<const PssMltIntegrator*>(integrator_.get()) != nullptr;
  if (!settings_.aniso_map_path.empty()) {
    if (!path_space_mcmc) throw Error("--aniso-map needs an MCMC integrator (mlt, gamlt or emlt)");
    check_output_path(settings_.aniso_map_path);
  }
  // A collimated beam lights the scene only through paths that light tracing makes: light
  // sampling (the path tracer's, the direct integrator's, the MCMC integrators' separate
  // direct image) never finds it.
  if (!desc.collimated_lights.empty()) {
    if (settings_.integrator == "pt" || settings_.integrator == "direct")
      warn(settings_.integrator +
           " cannot sample a collimated beam (nor can Mitsuba's path tracer): its light is "
           "missing; bdpt, ptracer and the MCMC integrators render it");
    else if (mcmc_ && settings_.direct_separate && given("--direct"))
      warn(
          "with --direct separate the collimated beam's direct light is missing (light "
          "sampling cannot find it); --direct mlt renders it");
    else if (mcmc_ && settings_.direct_separate) {
      settings_.direct_separate = false;
      // A note, not a warning: the render is what the scene means.
      std::fprintf(stderr,
                   "emlt: note: a collimated beam: the direct light is rendered by the "
                   "chains (--direct mlt), as light sampling cannot find the beam\n");
    }
  }
  // Bayesian Monte Carlo's weights are fixed by its prior, so its estimate is biased: the
  // path tracer and the MCMC integrators' direct pass must stay unbiased.
  if (settings_.direct_point_set == DirectPointSet::Bmc && settings_.integrator != "direct")
    throw Error("--direct-sampler bmc is biased (deterministic Bayesian quadrature weights) and " +
                settings_.integrator +
                " needs an unbiased direct-lighting estimate; only direct takes it");
  if (settings_.direct_point_set == DirectPointSet::Bmc && settings_.direct_samples > 1024)
    throw Error(
        "--direct-sampler bmc takes --direct-samples up to 1024 (its Gaussian-process "
        "system grows as the square of the directions)");
  // The path tracer and the chains' direct pass draw one light sample per vertex: a face is
  // chosen per sample there, whatever the option says.
  if (given("--env-face-counts") && settings_.env_face_counts == EnvFaceCounts::Fractional &&
      settings_.integrator != "direct")
    throw Error(
        "--env-face-counts fractional needs several light samples per point: only direct "
        "draws them (" +
        settings_.integrator +
        " draws one per vertex and chooses the "
        "face per sample)");
  if (given("--env-face-counts") && settings_.env_sampler != EnvSampler::CubeBalanced)
    warn("--env-face-counts is ignored without --env-sampler cube-balanced");
  if (given("--env-face-counts") && settings_.mis == MisHeuristic::SecondOrder)
    warn(
        "--env-face-counts is ignored under --mis second-order (its directions come from the "
        "light/BSDF mixture one by one)");
  if (settings_.integrator == "emlt" && given("--chains"))
    warn("--chains is ignored; the chains are the two ensembles (--ensemble-size)");
  if (given("--gamlt-cone-cell") && settings_.gamlt_cone_cells == 0.0)
    warn("--gamlt-cone-cell is ignored without --gamlt-cone cells");
  if (settings_.mis != MisHeuristic::SecondOrder)
    for (const char* flag : {"--mis-alpha", "--mis-alpha-estimate", "--mis-alpha-pilot",
                             "--mis-alpha-samples", "--mis-alpha-clamp"})
      if (given(flag)) warn(std::string(flag) + " is ignored without --mis second-order");
  // Adaptive sampling's cells follow the values it finds, so its estimate is biased; the
  // path tracer and the MCMC integrators' separate direct image must be unbiased.
  if (settings_.direct_point_set == DirectPointSet::Adaptive && settings_.integrator != "direct")
    throw Error(
        "--direct-sampler adaptive is a biased (deterministic, value-driven) estimate: "
        "only the direct integrator takes it, not " +
        settings_.integrator);
  if (settings_.direct_point_set != DirectPointSet::Adaptive)
    for (const char* flag :
         {"--adaptive-initial", "--adaptive-robustness", "--adaptive-parametrisation"})
      if (given(flag)) warn(std::string(flag) + " is ignored without --direct-sampler adaptive");
  if (!settings_.stats_path.empty()) check_directory_of(settings_.stats_path, "statistics");

  if (!r.log.empty() && r.reference.empty()) throw Error("--log " + r.log + ": needs --reference");
  if (!r.log.empty()) check_directory_of(r.log, "log");
  if (!r.reference.empty()) reference_ = read_image(r.reference);

  // Checkpoints: what this run is, checked against a checkpoint to resume before anything
  // is rendered or written.
  checkpoint_path_ = r.checkpoint.empty() ? r.resume : r.checkpoint;
  if (!checkpoint_path_.empty()) {
    check_directory_of(checkpoint_path_, "checkpoint");
    if (std::filesystem::path(checkpoint_path_) == std::filesystem::path(r.output))
      throw file_error(checkpoint_path_, "the checkpoint and the output image are the same file");
  }
  if (r.checkpoint_interval && checkpoint_path_.empty())
    throw Error("--checkpoint-interval needs --checkpoint FILE (or --resume FILE)");
  // Only a render that checkpoints needs it: describing the run hashes every scene file
  // (a 1 M-triangle mesh: 5 % of a short render).
  Run& run = *run_;
  if (!checkpoint_path_.empty())
    run.header_now = CheckpointHeader::describe(desc, settings_, r.defines);
  // Under MPI each rank saves its own share: rank 0 into FILE, rank r into FILE.rank<r>.
  const auto rank_file = [](const std::string& path) {
    return cluster::rank() == 0 ? path : path + ".rank" + std::to_string(cluster::rank());
  };
  resume_path_ = r.resume.empty() ? "" : rank_file(r.resume);
  std::optional<CheckpointHeader> resumed_header;
  std::string resume_state;
  uint32_t resume_format = checkpoint_file::kVersion;
  if (!r.resume.empty()) {
    checkpoint_file::Contents contents = checkpoint_file::read(resume_path_);
    resumed_header = CheckpointHeader::decode(contents.header, resume_path_);
    resumed_header->check_matches(run.header_now, resume_path_);
    resume_state = std::move(contents.state);
    resume_format = contents.version;
  }

  const bool root = cluster::is_root();  // under MPI only rank 0 prints and writes
  scene_ = Scene::build(std::move(desc), SceneBuildOptions{.direct_triangles = !r.bvh_only});
  for (const auto& w : scene_->warnings())
    if (root) warn(w);
  if (const std::string summary = divergence_summary(scene_->description());
      !summary.empty() && root)
    warn(summary);
  if (!r.reference.empty()) {
    if (reference_.width != scene_->camera().width() ||
        reference_.height != scene_->camera().height())
      throw file_error(r.reference, "reference is " + std::to_string(reference_.width) + "x" +
                                        std::to_string(reference_.height) + " but the render is " +
                                        std::to_string(scene_->camera().width()) + "x" +
                                        std::to_string(scene_->camera().height()));
    sees_emitter_ = directly_visible_emitters(*scene_);
  }
  if (!r.log.empty()) {
    run.log = std::make_unique<ConvergenceLog>(r.log, reference_, sees_emitter_,
                                               scene_->camera().width(), scene_->camera().height());
    settings_.snapshots = root ? static_cast<SnapshotSink*>(run.log.get()) : &run.no_snapshots;
    if (resumed_header) run.log->restore(resumed_header->log_header, resumed_header->log_rows);
  }
  if (!root) settings_.progress = false;
  setup_succeeded();  // every rank is ready (rank_agreement.h)

  run.control =
      std::make_unique<RenderControl>(checkpoint_path_.empty() ? "" : rank_file(checkpoint_path_),
                                      r.checkpoint_interval.value_or(600.0), [&run] {
                                        CheckpointHeader header = run.header_now;
                                        if (run.log) {
                                          header.log_header = run.log->header();
                                          header.log_rows = run.log->row_texts();
                                        }
                                        return header.encode();
                                      });
  run.control->set_resume_state(std::move(resume_state), resume_format);
  settings_.control = run.control.get();
}

RenderJob::~RenderJob() = default;

RenderResult RenderJob::run(ProgressReporter& progress) {
  try {
    return integrator_->render(*scene_, settings_, progress);
  } catch (const StateError& e) {
    throw file_error(resume_path_, std::string("cannot resume: ") + e.what());
  }
}

int RenderJob::checkpoints_written() const {
  return run_->control ? run_->control->checkpoints_written() : 0;
}

std::optional<ImageMetrics> RenderJob::against_reference(const Image& image) const {
  if (request_.reference.empty()) return std::nullopt;
  return compare_images(reference_, image, std::nullopt, &sees_emitter_);
}

}  // namespace emlt::cli
