#pragma once
// The render the checkpoint fuzz target (fuzz_checkpoint.cpp) resumes a saved integrator
// state into, shared with the unit tests of its regression inputs
// (tests/unit/fuzz_regression_test.cpp) so that both render exactly the same thing: the
// Cornell box at 4 x 4 pixels, 2 samples or mutations per pixel, 256 bootstrap samples, 4
// chains (EMLT: ensembles of 2), one thread. The seed corpus was written with these
// settings (make_checkpoint_corpus.py), since a state only loads into a render of the
// same image and budget; few chains keep the states small and the renders quick.
#include <array>
#include <memory>
#include <string>

#include "emlt/integrators/registry.h"
#include "emlt/run/integrator.h"
#include "emlt/run/progress.h"
#include "emlt/run/render_control.h"
#include "emlt/run/scene_settings.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"

namespace emlt::fuzz {

// The integrators of input modes 1 .. 8 ("pssmlt-bdpt": pssmlt with --pss-tracer bdpt).
inline constexpr std::array<const char*, 8> kCheckpointIntegrators = {
    "pt", "bdpt", "mlt", "gamlt", "emlt", "pssmlt", "pssmlt-bdpt", "mmlt"};

class CheckpointFixture {
 public:
  // Built once per process: a scene build (Embree) costs far more than a tiny render.
  static const CheckpointFixture& get() {
    static const CheckpointFixture fixture;
    return fixture;
  }

  const Scene& scene() const { return *scene_; }

  // What `emlt render scenes/cornell-box/scene.json --integrator NAME --spp 2 --mpp 2
  // --bootstrap 256 --chains 4 --ensemble-size 2 --threads 1 --width 4 --height 4 -q`
  // renders with (cli/render_command.cpp); for "pssmlt-bdpt", NAME is pssmlt with
  // --pss-tracer bdpt.
  RenderSettings settings(const std::string& integrator) const {
    RenderSettings s = defaults_;
    s.integrator = integrator == "pssmlt-bdpt" ? "pssmlt" : integrator;
    s.pss_bdpt = integrator == "pssmlt-bdpt";
    s.spp = 2;
    s.mutations_per_pixel = 2.0;
    s.bootstrap_samples = 256;
    s.chains = 4;
    s.ensemble_size = 2;
    s.threads = 1;
    s.mis = MisHeuristic::Power;
    s.direct_point_set = DirectPointSet::Independent;
    s.progress = false;
    return s;
  }

  // Renders with `integrator`, resumed from `state` as `emlt render --resume` does (an
  // empty state: a fresh render). Throws what the render throws: StateError for a state
  // it refuses.
  void resume(const std::string& integrator, std::string state) const {
    RenderSettings s = settings(integrator);
    RenderControl control("", 0.0, {});  // no checkpoint path: nothing is written
    control.set_resume_state(std::move(state));
    s.control = &control;
    ProgressReporter progress(false);
    make_integrator(s.integrator)->render(*scene_, s, progress);
  }

 private:
  CheckpointFixture() {
    SceneDescription desc =
        load_scene_description(EMLT_SOURCE_DIR "/scenes/cornell-box/scene.json");
    desc.camera.width = 4;
    desc.camera.height = 4;
    defaults_ = settings_for(desc.render);
    scene_ = Scene::build(std::move(desc));
  }

  std::unique_ptr<Scene> scene_;
  RenderSettings defaults_;
};

}  // namespace emlt::fuzz
