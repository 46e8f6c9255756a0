#pragma once
// Integrators turn a scene into an image. They are chosen by name (`--integrator`,
// integrators/registry.h), so comparing methods is a command-line flag.
#include <memory>
#include <string>
#include <vector>

#include "emlt/image/image.h"
#include "emlt/run/progress.h"
#include "emlt/scene/scene.h"
#include "emlt/settings/settings.h"

namespace emlt {

struct RenderResult {
  Image image;
  double seconds = 0.0;
  uint64_t samples = 0;  // camera samples (paths) traced
  int samples_per_pixel = 0;
  uint64_t invalid_samples = 0;  // NaN/Inf estimates dropped (should stay 0)
  // Stopped by a signal before its budget was done; the image is normalised for the work
  // done, which per_pixel gives (samples or mutations per pixel, a fraction when the stop
  // fell inside a pass).
  bool interrupted = false;
  double per_pixel = 0.0;
  std::string stopped_in;  // the phase the stop fell in, when not the main one ("direct light")
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual std::string name() const = 0;
  virtual RenderResult render(const Scene& scene, const RenderSettings& settings,
                              ProgressReporter& progress) const = 0;
};

// Throws emlt::Error for an unknown name.

}  // namespace emlt
