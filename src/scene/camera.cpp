#include "emlt/scene/camera.h"

#include <algorithm>

#include "emlt/core/error.h"
#include "emlt/core/warp.h"

namespace emlt {

Camera::Camera(const CameraDesc& desc, CameraFaults faults)
    : width_(desc.cropped() ? desc.crop_width : desc.width),
      height_(desc.cropped() ? desc.crop_height : desc.height),
      film_width_(desc.width),
      film_height_(desc.height),
      crop_offset_(desc.cropped() ? Vec2(float(desc.crop_x), float(desc.crop_y)) : Vec2(0.0f)),
      // Mitsuba filters the window as an image of its own: samples fall inside it only.
      filter_(desc.filter, width_, height_),
      aperture_radius_(desc.aperture_radius),
      focus_distance_(desc.focus_distance),
      orthographic_(desc.projection == CameraDesc::Projection::Orthographic) {
  const Mat4& m = desc.to_world;
  // Camera space has +x pointing to the image's left, so the image's right is -x.
  right_ = -glm::normalize(Vec3(m[0]));
  up_ = glm::normalize(Vec3(m[1]));
  forward_ = glm::normalize(Vec3(m[2]));
  position_ = Vec3(m[3]);
  forward_frame_ = Frame(forward_);

  // The whole film frames the view, whatever part of it is rendered.
  const float aspect = float(film_width_) / float(film_height_);
  const float tan_half = std::tan(glm::radians(desc.fov_degrees) * 0.5f);
  bool fov_is_x = true;
  switch (desc.fov_axis) {
    case CameraDesc::FovAxis::X: fov_is_x = true; break;
    case CameraDesc::FovAxis::Y: fov_is_x = false; break;
    case CameraDesc::FovAxis::Smaller: fov_is_x = film_width_ <= film_height_; break;
    case CameraDesc::FovAxis::Larger: fov_is_x = film_width_ >= film_height_; break;
  }
  if (fov_is_x) {
    tan_half_x_ = tan_half;
    tan_half_y_ = tan_half / aspect;
  } else {
    tan_half_y_ = tan_half;
    tan_half_x_ = tan_half * aspect;
  }
  // The part of the plane the rendered image covers, over which W_e integrates to one.
  image_plane_area_ = 4.0f * tan_half_x_ * tan_half_y_ * float(width_) * float(height_) /
                      (float(film_width_) * float(film_height_));
  if (orthographic_) {
    // Mitsuba's orthographic film spans x in [-1, 1] and y in [-1/aspect, 1/aspect] of
    // camera space, on the z = 0 plane; to_world's scale sizes it (so m's columns are not
    // normalised here). The image's right is camera -x, its top +y.
    aperture_radius_ = 0.0f;
    ortho_centre_ = Vec3(m[3]);
    ortho_half_right_ = -Vec3(m[0]);
    ortho_half_up_ = Vec3(m[1]) / aspect;
    // Mitsuba sizes it by its sides' lengths, as here (a to_world that shears is not square);
    // W_e integrates to one over the part a crop window renders.
    const float window = float(width_) * float(height_) / (float(film_width_) * float(film_height_));
    ortho_inv_area_ =
        1.0f / (4.0f * glm::length(ortho_half_right_) * glm::length(ortho_half_up_) * window);
    if (faults.orthographic_unscaled_area) ortho_inv_area_ = aspect / (4.0f * window);
    film_pixel_size_ = std::min(2.0 * glm::length(DVec3(ortho_half_right_)) / film_width_,
                                2.0 * glm::length(DVec3(ortho_half_up_)) / film_height_);
  }
  faults_ = faults;

  // Angles between the centre's ray and its neighbours one pixel right and down, each as
  // atan2(|a x b|, a . b) in double, which stays accurate for the tiny angles involved.
  const Vec2 centre(0.5f * float(width_), 0.5f * float(height_));
  const DVec3 d0(generate_ray_from_lens_point(centre, position_).direction);
  const DVec3 dx(generate_ray_from_lens_point(centre + Vec2(1.0f, 0.0f), position_).direction);
  const DVec3 dy(generate_ray_from_lens_point(centre + Vec2(0.0f, 1.0f), position_).direction);
  const auto angle = [](const DVec3& a, const DVec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
  };
  radians_per_pixel_ = std::min(angle(d0, dx), angle(d0, dy));
}

Vec2 Camera::film_ndc(const Vec2& raster) const {
  const Vec2 on_film = raster + crop_offset_;
  return {2.0f * on_film.x / float(film_width_) - 1.0f,
          1.0f - 2.0f * on_film.y / float(film_height_)};
}

Vec3 Camera::film_direction_local(const Vec2& raster) const {
  const Vec2 ndc = film_ndc(raster);
  return {ndc.x * tan_half_x_, ndc.y * tan_half_y_, 1.0f};
}

Ray Camera::generate_ray(const Vec2& raster, const Vec2& u_lens) const {
  if (orthographic_) return generate_ray_from_lens_point(raster, position_);
  const Vec3 local = film_direction_local(raster);
  const Vec3 through = local.x * right_ + local.y * up_ + forward_;  // z = 1 plane, world
  Ray ray;
  if (is_pinhole()) {
    ray.origin = position_;
    ray.direction = glm::normalize(through);
    return ray;
  }
  // Thin lens: every ray through the same film point meets on the focus plane.
  const Vec3 focus_point = position_ + through * focus_distance_;
  const Vec2 disk = square_to_uniform_disk_concentric(u_lens) * aperture_radius_;
  ray.origin = position_ + disk.x * right_ + disk.y * up_;
  ray.direction = glm::normalize(focus_point - ray.origin);
  return ray;
}

Ray Camera::generate_ray_from_lens_point(const Vec2& raster, const Vec3& lens_point) const {
  if (orthographic_) {  // the film point is the ray's origin: no lens point to keep
    const Vec2 ndc = film_ndc(raster);
    return {ortho_centre_ + ndc.x * ortho_half_right_ + ndc.y * ortho_half_up_, forward_};
  }
  const Vec3 local = film_direction_local(raster);
  const Vec3 through = local.x * right_ + local.y * up_ + forward_;
  Ray ray;
  if (is_pinhole()) {
    ray.origin = position_;
    ray.direction = glm::normalize(through);
    return ray;
  }
  ray.origin = lens_point;
  ray.direction = glm::normalize(position_ + through * focus_distance_ - lens_point);
  return ray;
}

std::optional<Vec2> Camera::film_raster(const Vec3& p) const {
  // generate_ray_from_lens_point inverted: the film's sides are orthogonal.
  const Vec3 q = p - ortho_centre_;
  const float ndc_x =
      glm::dot(q, ortho_half_right_) / glm::dot(ortho_half_right_, ortho_half_right_);
  const float ndc_y = glm::dot(q, ortho_half_up_) / glm::dot(ortho_half_up_, ortho_half_up_);
  const Vec2 raster = Vec2((ndc_x + 1.0f) * 0.5f * float(film_width_),
                           (1.0f - ndc_y) * 0.5f * float(film_height_)) -
                      crop_offset_;
  if (!(raster.x >= 0.0f && raster.x < float(width_) && raster.y >= 0.0f &&
        raster.y < float(height_)))
    return std::nullopt;
  return raster;
}

bool Camera::on_film(const Vec3& p) const {
  if (!orthographic_ || !film_raster(p)) return false;
  // A projection (sample_direct) lands on the plane to the rounding of the points involved,
  // which may lie much farther out than the film: a generous tolerance.
  const float scale = std::max({1.0f, glm::length(ortho_centre_), glm::length(p)});
  return std::abs(glm::dot(p - ortho_centre_, forward_)) <= 1e-3f * scale;
}

std::optional<Vec2> Camera::raster_position(const Vec3& p, const Vec3& w) const {
  // An orthographic camera sees a single direction: no sampled direction lands on its film.
  if (orthographic_) return std::nullopt;
  const float cos_theta = glm::dot(w, forward_);
  if (cos_theta <= 0.0f) return std::nullopt;
  // Where the ray crosses the focus plane, seen from the lens centre, fixes the pixel.
  const float plane_distance = is_pinhole() ? 1.0f : focus_distance_;
  const Vec3 q = (p + w * (plane_distance / cos_theta)) - position_;
  const float depth = glm::dot(q, forward_);
  if (depth <= 0.0f) return std::nullopt;
  const float x = glm::dot(q, right_) / depth, y = glm::dot(q, up_) / depth;
  const Vec2 raster = Vec2((x / tan_half_x_ + 1.0f) * 0.5f * float(film_width_),
                           (1.0f - y / tan_half_y_) * 0.5f * float(film_height_)) -
                      crop_offset_;
  if (!(raster.x >= 0.0f && raster.x < float(width_) && raster.y >= 0.0f &&
        raster.y < float(height_)))
    return std::nullopt;
  return raster;
}

float Camera::importance(const Vec3& p, const Vec3& w) const {
  if (orthographic_) return glm::dot(w, forward_) > 0.0f && film_raster(p) ? ortho_inv_area_ : 0.0f;
  if (!raster_position(p, w)) return 0.0f;
  return importance_on_film(glm::dot(w, forward_));
}

float Camera::importance_on_film(float cos_theta) const {
  const float lens_area = is_pinhole() ? 1.0f : kPi * aperture_radius_ * aperture_radius_;
  const float cos2 = cos_theta * cos_theta;
  return 1.0f / (image_plane_area_ * lens_area * cos2 * cos2);
}

void Camera::pdf_emission(const Vec3& w, float* pdf_position, float* pdf_direction) const {
  if (orthographic_) {  // x0 follows from x1; the film's density goes to x1 (camera.h)
    *pdf_position = 1.0f;
    *pdf_direction = glm::dot(w, forward_) > 0.0f ? ortho_inv_area_ : 0.0f;
    return;
  }
  const float cos_theta = glm::dot(w, forward_);
  const float lens_area = is_pinhole() ? 1.0f : kPi * aperture_radius_ * aperture_radius_;
  *pdf_position = 1.0f / lens_area;
  *pdf_direction = cos_theta > 0.0f ? 1.0f / (image_plane_area_ * cos_theta * cos_theta * cos_theta)
                                    : 0.0f;
}

float Camera::orthographic_hit_density(float abs_cos, float distance_squared) const {
  const float density = abs_cos * ortho_inv_area_;
  if (faults_.orthographic_spreading_density && distance_squared > 0.0f)
    return density / distance_squared;
  return density;
}

std::optional<CameraDirectSample> Camera::sample_direct(const Vec3& ref, const Vec2& u_lens) const {
  if (orthographic_) {
    // The one film point that sees ref: its projection along -d, if ref lies ahead.
    CameraDirectSample s;
    s.distance = glm::dot(ref - ortho_centre_, forward_);
    if (!(s.distance > 0.0f)) return std::nullopt;
    s.lens_point = ref - s.distance * forward_;
    const auto raster = film_raster(s.lens_point);
    if (!raster) return std::nullopt;
    s.raster = *raster;
    s.wi = -forward_;
    s.importance = Rgb(ortho_inv_area_);
    s.pdf = 1.0f;
    return s;
  }
  CameraDirectSample s;
  const Vec2 disk = is_pinhole() ? Vec2(0.0f)
                                 : square_to_uniform_disk_concentric(u_lens) * aperture_radius_;
  s.lens_point = position_ + disk.x * right_ + disk.y * up_;
  const Vec3 to_lens = s.lens_point - ref;
  s.distance = glm::length(to_lens);
  if (!(s.distance > 0.0f)) return std::nullopt;
  s.wi = to_lens / s.distance;
  const auto raster = raster_position(s.lens_point, -s.wi);
  if (!raster) return std::nullopt;
  s.raster = *raster;
  // raster_position has just found -wi on the film.
  s.importance = Rgb(importance_on_film(glm::dot(-s.wi, forward_)));
  const float lens_area = is_pinhole() ? 1.0f : kPi * aperture_radius_ * aperture_radius_;
  const float cos_lens = std::abs(glm::dot(forward_, s.wi));
  s.pdf = s.distance * s.distance / (cos_lens * lens_area);
  return s;
}

}  // namespace emlt
