#include "emlt/core/frame.h"
#include "emlt/core/warp.h"
#include "emlt/scene/light.h"

namespace emlt {

namespace {

Vec3 point_on_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec2& u) {
  const Vec2 bary = square_to_uniform_triangle(u);
  return (1.0f - bary.x - bary.y) * a + bary.x * b + bary.y * c;
}

}  // namespace

TriangleLight::TriangleLight(const Vec3& a, const Vec3& b, const Vec3& c, const Rgb& radiance)
    : a_(a), b_(b), c_(c), radiance_(radiance) {
  const Vec3 cross = glm::cross(b - a, c - a);
  const float length = glm::length(cross);
  area_ = 0.5f * length;
  // A degenerate triangle keeps a zero normal and area: it has no power, so the light set
  // never picks it, and every sampling routine below refuses it.
  normal_ = length > 0.0f ? cross / length : Vec3(0.0f);
}

Rgb TriangleLight::power() const {
  // Lambertian emitter: the cosine-weighted hemisphere integral of L is pi * L per unit area.
  return kPi * area_ * radiance_;
}

std::optional<DirectLightSample> TriangleLight::sample_direct(const Vec3& ref,
                                                              const Vec2& u) const {
  if (area_ <= 0.0f) return std::nullopt;
  const Vec3 p = point_on_triangle(a_, b_, c_, u);
  const Vec3 to_light = p - ref;
  const float distance_squared = glm::dot(to_light, to_light);
  if (!(distance_squared > 0.0f)) return std::nullopt;
  const float distance = std::sqrt(distance_squared);
  const Vec3 wi = to_light / distance;
  // One-sided: a receiver behind the emitting face sees nothing of it.
  const float cos_light = -glm::dot(normal_, wi);
  if (!(cos_light > 0.0f)) return std::nullopt;

  DirectLightSample sample;
  sample.position = p;
  sample.normal = normal_;
  sample.wi = wi;
  sample.distance = distance;
  sample.radiance = radiance_;
  sample.pdf = distance_squared / (cos_light * area_);
  if (!std::isfinite(sample.pdf)) return std::nullopt;
  return sample;
}

float TriangleLight::pdf_direct(const Vec3& ref, const Vec3& p, const Vec3& n,
                                const Vec3& wi) const {
  // The light's own normal decides the emitting side: the caller's `n` may have been
  // flipped towards the ray by the intersector.
  (void)n;
  if (area_ <= 0.0f) return 0.0f;
  const Vec3 to_light = p - ref;
  const float distance_squared = glm::dot(to_light, to_light);
  const float cos_light = -glm::dot(normal_, wi);
  if (!(distance_squared > 0.0f) || !(cos_light > 0.0f)) return 0.0f;
  const float pdf = distance_squared / (cos_light * area_);
  return std::isfinite(pdf) ? pdf : 0.0f;
}

std::optional<EmissionSample> TriangleLight::sample_emission(const Vec2& u_position,
                                                             const Vec2& u_direction) const {
  if (area_ <= 0.0f) return std::nullopt;
  const Vec3 p = point_on_triangle(a_, b_, c_, u_position);
  const Vec3 local = square_to_cosine_hemisphere(u_direction);
  const float pdf_direction = cosine_hemisphere_pdf(local);
  if (!(pdf_direction > 0.0f)) return std::nullopt;
  const Vec3 direction = glm::normalize(Frame(normal_).to_world(local));

  EmissionSample sample;
  // The origin is nudged off the triangle (spawn_ray) so that tracing the ray cannot
  // re-hit the emitter itself; the shift is far below any scene feature size.
  sample.ray = spawn_ray(p, normal_, direction);
  sample.normal = normal_;
  sample.radiance = radiance_;
  sample.pdf_position = 1.0f / area_;
  sample.pdf_direction = pdf_direction;
  return sample;
}

void TriangleLight::pdf_emission(const Vec3& p, const Vec3& n, const Vec3& w,
                                 float* pdf_position, float* pdf_direction) const {
  (void)p;
  (void)n;
  const float cos_out = glm::dot(normal_, w);
  if (pdf_position) *pdf_position = area_ > 0.0f ? 1.0f / area_ : 0.0f;
  if (pdf_direction) *pdf_direction = cos_out > 0.0f ? cos_out * kInvPi : 0.0f;
}

Rgb TriangleLight::emitted(const Vec3& n, const Vec3& w) const {
  (void)n;  // see pdf_direct: the emitting side is a property of the light
  return glm::dot(normal_, w) > 0.0f ? radiance_ : Rgb(0.0f);
}

}  // namespace emlt
