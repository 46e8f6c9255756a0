#pragma once
// Perspective camera: pinhole (aperture 0) or thin lens; or an orthographic one (see
// is_orthographic). Raster coordinates are pixels, x in [0, width) to the right, y in
// [0, height) downwards, of the image rendered: with a crop window (CameraDesc) that is the
// window, placed at its offset on the film that frames the view. The importance W_e is
// normalised over the whole image rendered (pbrt's convention): it integrates to one over
// the lens and all directions that reach the image, i.e. W_e = 1 / (A_film * A_lens * cos^4),
// with A_film the image's area on the plane at distance 1 and A_lens = 1 for a pinhole. A pixel
// value is therefore (width * height) times the film measurement restricted to that pixel:
// light tracing with N paths splats W_e * L * G / pdf * (width * height / N).
#include <optional>

#include "emlt/scene/description.h"
#include "emlt/scene/ray.h"

namespace emlt {

struct CameraDirectSample {
  Vec3 lens_point{0.0f};  // point on the lens
  Vec3 wi{0.0f};          // unit direction ref -> lens_point
  float distance = 0.0f;
  Vec2 raster{0.0f};
  Rgb importance{0.0f};   // W_e(lens_point, -wi)
  float pdf = 0.0f;       // solid angle density at ref
};

class Camera {
 public:
  explicit Camera(const CameraDesc& desc);

  int width() const { return width_; }
  // The film's reconstruction filter: where camera samples of a pixel go, and which
  // pixels a light-side contribution lands in.
  const PixelFilter& filter() const { return filter_; }
  int height() const { return height_; }
  float aperture_radius() const { return aperture_radius_; }
  bool is_pinhole() const { return aperture_radius_ <= 0.0f; }
  // Parallel rays from a rectangle (every ray the same direction): a delta in direction,
  // which the path layer has no vertex for. Only the integrators that just trace camera
  // rays (pt, direct) render it; `emlt render` refuses the others.
  bool is_orthographic() const { return orthographic_; }
  const Vec3& position() const { return position_; }
  const Vec3& forward() const { return forward_; }
  // The frame about the forward axis (a lens vertex's shading frame), built once.
  const Frame& forward_frame() const { return forward_frame_; }

  // Primary ray through raster position `raster` using lens sample `u_lens`.
  Ray generate_ray(const Vec2& raster, const Vec2& u_lens) const;
  // The ray from a given point on the lens through raster position `raster` (thin lens:
  // aimed at that position's point on the focus plane; pinhole: the lens point is the
  // camera position). MLT's lens perturbation moves the image point and keeps the lens
  // point, so the path's lens vertex does not change.
  Ray generate_ray_from_lens_point(const Vec2& raster, const Vec3& lens_point) const;

  // Raster position of the ray leaving lens point p in direction w, if it lands on film.
  std::optional<Vec2> raster_position(const Vec3& p, const Vec3& w) const;
  // Importance W_e(p, w); zero when w misses the film.
  float importance(const Vec3& p, const Vec3& w) const;
  // Densities of generate_ray with uniform raster and lens samples: position on the lens
  // (area; 1 for a pinhole, a delta handled by the path layer) and direction (solid angle).
  void pdf_emission(const Vec3& w, float* pdf_position, float* pdf_direction) const;

  // Connects a scene point to the lens (light tracing, t = 1 strategies).
  std::optional<CameraDirectSample> sample_direct(const Vec3& ref, const Vec2& u_lens) const;

  // Angular size of one pixel at the image centre (radians, the smaller of its two sides),
  // for MLT's caustic-perturbation heuristic. Computed once here: the perturbations ask for
  // it at every step, and it costs three camera rays and two atan2.
  double radians_per_pixel() const { return radians_per_pixel_; }

 private:
  // A raster position's place on the whole film, each axis in [-1, 1] (+y up).
  Vec2 film_ndc(const Vec2& raster) const;
  Vec3 film_direction_local(const Vec2& raster) const;  // camera space, z = 1 plane
  // W_e of a direction at cos_theta to the forward axis that lands on the film.
  float importance_on_film(float cos_theta) const;

  int width_, height_;            // the image rendered (the crop window, if any)
  int film_width_, film_height_;  // the film that frames the view
  Vec2 crop_offset_{0.0f};        // the window's top-left pixel on that film
  PixelFilter filter_;
  Vec3 position_, forward_, right_, up_;  // world; right_ = image +x
  Frame forward_frame_;
  float tan_half_x_, tan_half_y_;         // film half extents on the z = 1 plane
  float image_plane_area_;                // at distance 1
  float aperture_radius_, focus_distance_;
  bool orthographic_ = false;
  // Orthographic: the film rectangle's centre and its half extents (world, with to_world's
  // scale), the image's right and up.
  Vec3 ortho_centre_{0.0f}, ortho_half_right_{0.0f}, ortho_half_up_{0.0f};
  double radians_per_pixel_ = 0.0;
};

}  // namespace emlt
