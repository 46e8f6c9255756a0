#pragma once
// A render as a front end asks for it. The command line (`emlt render`) and the Python module
// (`emlt.render`) both fill a RenderRequest and run a RenderJob, so that the same settings
// give the same image, bit for bit, and bad input is refused in the same words.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emlt/image/image.h"
#include "emlt/image/image_metrics.h"
#include "emlt/run/integrator.h"
#include "emlt/run/progress.h"
#include "emlt/scene/scene.h"
#include "emlt/settings/settings.h"

namespace emlt::cli {

struct RenderRequest {
  std::string scene;
  std::vector<std::string> defines;  // "name=value", as -D takes them
  std::optional<std::string> integrator;
  std::optional<int> width, height;
  // The text given for each declared render option (render_options()), by flag; only the
  // options given (a time budget alone, for one, drops the scene's sample count).
  std::map<std::string, std::string> options;
  std::string output;  // the image the front end writes ("" none): checked before rendering
  std::string reference, log;
  std::string checkpoint, resume;
  std::optional<double> checkpoint_interval;
  bool progress = true;
  bool strict = false;
  bool bvh_only = false;
};

class RenderJob {
 public:
  using Warn = std::function<void(const std::string&)>;

  // Loads and builds the scene, settles its settings (the engine's defaults, the scene
  // file's, the request's) and reads the checkpoint to resume; throws emlt::Error for
  // anything the render would refuse, before it starts. `warn` receives each warning, one
  // line without a prefix.
  RenderJob(RenderRequest request, const Warn& warn);
  ~RenderJob();
  RenderJob(const RenderJob&) = delete;
  RenderJob& operator=(const RenderJob&) = delete;

  // Renders to the budget, or until interruption::request_stop(); the image is normalised
  // for the work done either way. Throws emlt::Error naming the checkpoint when its state
  // cannot be resumed.
  RenderResult run(ProgressReporter& progress);

  const RenderRequest& request() const { return request_; }
  const RenderSettings& settings() const { return settings_; }
  const Integrator& integrator() const { return *integrator_; }
  const Scene& scene() const { return *scene_; }
  // Whether the integrator's work is counted in mutations (an MCMC integrator).
  bool mcmc() const { return mcmc_; }
  // Where checkpoints go ("" none) and how many this job has written.
  const std::string& checkpoint_path() const { return checkpoint_path_; }
  int checkpoints_written() const;
  // The metrics of `image` against the request's reference; nullopt without one.
  std::optional<ImageMetrics> against_reference(const Image& image) const;

 private:
  struct Run;  // what only the render itself uses (the convergence log, the control)

  RenderRequest request_;
  RenderSettings settings_;
  std::unique_ptr<Integrator> integrator_;
  std::unique_ptr<Scene> scene_;
  bool mcmc_ = false;
  std::string checkpoint_path_;
  std::string resume_path_;
  Image reference_;
  std::vector<uint8_t> sees_emitter_;
  std::unique_ptr<Run> run_;
};

}  // namespace emlt::cli
