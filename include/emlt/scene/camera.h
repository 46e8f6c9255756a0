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
//
// Orthographic: the film is a rectangle of area A (world units) facing its forward axis d,
// and W_e(x0, w) = delta(w - d) / A, normalised over the film in the same way. Its lens
// vertex x0 is therefore no free vertex: it is the projection of the first scene vertex x1
// onto the film along -d, and the measurement is (1/A) * integral of L(x1 -> -d) |cos1| V
// dA(x1). The path layer keeps x0 as a discrete vertex (density 1, like a pinhole's point),
// gives the edge x0 x1 the factor |cos1| alone (no cosine at the film, no 1/d^2: the rays
// are parallel) and x1 the area density |cos1| / A from the camera side
// (orthographic_hit_density); a light subpath vertex reaches the camera by its projection
// (sample_direct), with W_e = 1/A; no walk hits the film.
#include <optional>

#include "emlt/scene/description.h"
#include "emlt/scene/ray.h"

namespace emlt {

struct CameraDirectSample {
  Vec3 lens_point{0.0f};  // point on the lens (orthographic: ref's projection on the film)
  Vec3 wi{0.0f};          // unit direction ref -> lens_point
  float distance = 0.0f;
  Vec2 raster{0.0f};
  Rgb importance{0.0f};   // W_e(lens_point, -wi) (orthographic: 1/A, the delta left out)
  float pdf = 0.0f;       // solid angle density at ref (orthographic: 1, a discrete choice)
};

// Known mistakes the tests inject to show they notice them (SceneBuildOptions).
struct CameraFaults {
  // The first vertex an orthographic camera's ray reaches given a perspective camera's
  // density, divided by its squared distance from the film as if the rays spread out.
  bool orthographic_spreading_density = false;
  // An orthographic film's area taken in camera space, without to_world's scale (Mitsuba
  // normalises W_e by the scaled film's).
  bool orthographic_unscaled_area = false;
};

class Camera {
 public:
  explicit Camera(const CameraDesc& desc, CameraFaults faults = {});

  int width() const { return width_; }
  // The film's reconstruction filter: where camera samples of a pixel go, and which
  // pixels a light-side contribution lands in.
  const PixelFilter& filter() const { return filter_; }
  int height() const { return height_; }
  float aperture_radius() const { return aperture_radius_; }
  bool is_pinhole() const { return aperture_radius_ <= 0.0f; }
  // Parallel rays from a rectangle (every ray the same direction d): a delta in direction.
  // Its lens vertex is a point on the film fixed by the vertex it sees (see above; the path
  // layer gives it a kind of its own, VertexKind::OrthographicCamera).
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

  // Raster position of the ray leaving lens point p in direction w, if it lands on film
  // (orthographic: none; a sampled direction never is d, see film_raster).
  std::optional<Vec2> raster_position(const Vec3& p, const Vec3& w) const;
  // Orthographic: the raster position of film point p, if it lies inside the film.
  std::optional<Vec2> film_raster(const Vec3& p) const;
  // Orthographic: whether p lies on the film (its plane, to rounding, and inside it).
  bool on_film(const Vec3& p) const;
  // Importance W_e(p, w); zero when w misses the film. Orthographic: 1/A for a point p
  // inside the film and any w into the half space ahead (the delta in w is the path
  // layer's: x0 is always x1's projection).
  float importance(const Vec3& p, const Vec3& w) const;
  // Densities of generate_ray with uniform raster and lens samples: position on the lens
  // (area; 1 for a pinhole, a delta handled by the path layer) and direction (solid angle).
  // Orthographic: position 1 (x0 follows from x1, see above) and, as "direction", the
  // film's area density 1/A, which orthographic_hit_density carries onto the vertex hit.
  void pdf_emission(const Vec3& w, float* pdf_position, float* pdf_direction) const;
  // Orthographic: the area density of the vertex a camera ray reaches, at |cos| abs_cos
  // between d and its normal and squared distance distance_squared from the film (unused:
  // parallel rays do not spread): the film's 1/A on the projected area, abs_cos / A.
  float orthographic_hit_density(float abs_cos, float distance_squared) const;

  // Connects a scene point to the lens (light tracing, t = 1 strategies). Orthographic: the
  // point's projection on the film, if it lies ahead of the film and projects inside it.
  std::optional<CameraDirectSample> sample_direct(const Vec3& ref, const Vec2& u_lens) const;

  // Angular size of one pixel at the image centre (radians, the smaller of its two sides),
  // for MLT's caustic-perturbation heuristic. Computed once here: the perturbations ask for
  // it at every step, and it costs three camera rays and two atan2.
  double radians_per_pixel() const { return radians_per_pixel_; }
  // Orthographic: the smaller side of one pixel on the film (world units), what a pixel's
  // angle is to a perspective camera (0 for those).
  double film_pixel_size() const { return film_pixel_size_; }

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
  // scale), the image's right and up; 1 / its area.
  Vec3 ortho_centre_{0.0f}, ortho_half_right_{0.0f}, ortho_half_up_{0.0f};
  float ortho_inv_area_ = 0.0f;
  CameraFaults faults_;
  double radians_per_pixel_ = 0.0, film_pixel_size_ = 0.0;
};

}  // namespace emlt
