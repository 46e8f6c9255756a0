#include "emlt/scene/visible_emitters.h"

#include "emlt/scene/scene.h"

namespace emlt {

std::vector<uint8_t> directly_visible_emitters(const Scene& scene) {
  const Camera& camera = scene.camera();
  std::vector<uint8_t> mask(size_t(camera.width()) * camera.height(), 0);
  for (int y = 0; y < camera.height(); ++y)
    for (int x = 0; x < camera.width(); ++x) {
      bool sees = false;
      for (int j = 0; j < 3 && !sees; ++j)
        for (int i = 0; i < 3 && !sees; ++i) {
          const Vec2 raster(float(x) + (float(i) + 0.5f) / 3.0f,
                            float(y) + (float(j) + 0.5f) / 3.0f);
          SurfaceHit hit;
          if (scene.intersect(camera.generate_ray(raster, Vec2(0.5f)), hit))
            sees = hit.light != nullptr;
          else
            sees = scene.environment() != nullptr;
        }
      mask[size_t(y) * camera.width() + x] = sees;
    }
  return mask;
}

}  // namespace emlt
