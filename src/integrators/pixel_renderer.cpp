#include "emlt/integrators/pixel_renderer.h"

#include "emlt/run/pass_runner.h"

namespace emlt {

namespace {

// One camera ray through the pixel (its filter's jitter, then the lens), and the radiance
// arriving along it.
class CameraRayStep final : public PixelSampleStep {
 public:
  CameraRayStep(const Camera& camera, const RadianceEstimator& radiance)
      : camera_(camera), radiance_(radiance) {}

  void sample(int x, int y, Rng& rng, DVec3& pixel_sum, TileOutput& out) override {
    const Vec2 jitter = rng.uniform2();
    const Vec2 u_lens = rng.uniform2();
    const FilterSample pixel = camera_.filter().sample(x, y, jitter);
    const Ray ray = camera_.generate_ray(pixel.raster, u_lens);
    Rgb value = radiance_(ray, rng);
    // The filter's weight (negative in a negative lobe) after the check, as Mitsuba weighs
    // only valid, non-negative radiance.
    if (out.invalid.keep(value)) pixel_sum += DVec3(value) * double(pixel.weight);
  }

 private:
  const Camera& camera_;
  const RadianceEstimator& radiance_;
};

}  // namespace

RenderResult render_pixels(const Scene& scene, const RenderSettings& settings,
                           ProgressReporter& progress, const RadianceEstimator& radiance,
                           PixelRenderState& state, const std::function<void()>& on_pause) {
  CameraRayStep step(scene.camera(), radiance);
  PassRunner runner(scene, settings, progress, step, state);
  return runner.run(on_pause);
}

RenderResult render_pixels(const Scene& scene, const RenderSettings& settings,
                           ProgressReporter& progress, const RadianceEstimator& radiance) {
  CameraRayStep step(scene.camera(), radiance);
  return PassRunner(scene, settings, progress, step).render();
}

}  // namespace emlt
