#include "emlt/integrators/pixel_renderer.h"

#include "emlt/run/pass_runner.h"

namespace emlt {

namespace {

// One camera ray through the pixel (its filter's jitter, then the lens), and the radiance
// arriving along it.
class CameraRayStep final : public PixelSampleStep {
 public:
  CameraRayStep(const Camera& camera, const PixelRadianceEstimator& radiance)
      : camera_(camera), radiance_(radiance) {}

  void sample(int x, int y, Rng& rng, DVec3& pixel_sum, TileOutput& out) override {
    float weight = 0.0f;
    const Ray ray = pixel_camera_ray(camera_, x, y, rng, &weight);
    Rgb value = radiance_(x, y, ray, rng);
    // The filter's weight (negative in a negative lobe) after the check, as Mitsuba weighs
    // only valid, non-negative radiance.
    if (out.invalid.keep(value)) pixel_sum += DVec3(value) * double(weight);
  }

 private:
  const Camera& camera_;
  const PixelRadianceEstimator& radiance_;
};

PixelRadianceEstimator at_any_pixel(const RadianceEstimator& radiance) {
  return [&radiance](int, int, const Ray& ray, Rng& rng) { return radiance(ray, rng); };
}

}  // namespace

Ray pixel_camera_ray(const Camera& camera, int x, int y, Rng& rng, float* filter_weight) {
  const Vec2 jitter = rng.uniform2();
  const Vec2 u_lens = rng.uniform2();
  const FilterSample pixel = camera.filter().sample(x, y, jitter);
  if (filter_weight) *filter_weight = pixel.weight;
  return camera.generate_ray(pixel.raster, u_lens);
}

RenderResult render_pixels_at(const Scene& scene, const RenderSettings& settings,
                              ProgressReporter& progress, const PixelRadianceEstimator& radiance,
                              PixelRenderState& state, const std::function<void()>& on_pause) {
  CameraRayStep step(scene.camera(), radiance);
  PassRunner runner(scene, settings, progress, step, state);
  return runner.run(on_pause);
}

RenderResult render_pixels_at(const Scene& scene, const RenderSettings& settings,
                              ProgressReporter& progress, const PixelRadianceEstimator& radiance) {
  CameraRayStep step(scene.camera(), radiance);
  return PassRunner(scene, settings, progress, step).render();
}

RenderResult render_pixels(const Scene& scene, const RenderSettings& settings,
                           ProgressReporter& progress, const RadianceEstimator& radiance,
                           PixelRenderState& state, const std::function<void()>& on_pause) {
  return render_pixels_at(scene, settings, progress, at_any_pixel(radiance), state, on_pause);
}

RenderResult render_pixels(const Scene& scene, const RenderSettings& settings,
                           ProgressReporter& progress, const RadianceEstimator& radiance) {
  return render_pixels_at(scene, settings, progress, at_any_pixel(radiance));
}

}  // namespace emlt
