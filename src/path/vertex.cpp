#include "emlt/path/vertex.h"

#include "emlt/scene/scene.h"

namespace emlt {

Vec3 direction_between(const PathVertex& from, const PathVertex& to) {
  if (to.is_environment()) return to.sky_direction;
  if (from.is_environment()) return -from.sky_direction;
  const Vec3 d = to.position - from.position;
  const float length = glm::length(d);
  return length > 0.0f ? d / length : Vec3(0.0f);
}

float abs_cos_at(const PathVertex& v, const Vec3& w) {
  if (v.is_environment()) return 1.0f;
  return std::abs(glm::dot(v.normal, w));
}

float geometry_term(const PathVertex& a, const PathVertex& b) {
  if (a.is_environment() && b.is_environment()) return 0.0f;
  const Vec3 w = direction_between(a, b);
  if (a.is_environment() || b.is_environment()) return abs_cos_at(a, w) * abs_cos_at(b, w);
  const Vec3 d = b.position - a.position;
  const float distance_squared = glm::dot(d, d);
  if (!(distance_squared > 0.0f)) return 0.0f;
  const float g = abs_cos_at(a, w) * abs_cos_at(b, w) / distance_squared;
  return std::isfinite(g) ? g : 0.0f;
}

float solid_angle_to_vertex_measure(float pdf_solid_angle, const PathVertex& from,
                                    const PathVertex& to) {
  if (to.is_environment()) return pdf_solid_angle;  // the sky's measure is solid angle
  const Vec3 d = to.position - from.position;
  const float distance_squared = glm::dot(d, d);
  if (!(distance_squared > 0.0f)) return 0.0f;
  const float pdf =
      pdf_solid_angle * abs_cos_at(to, d / std::sqrt(distance_squared)) / distance_squared;
  return std::isfinite(pdf) ? pdf : 0.0f;
}

PathVertex make_surface_vertex(const SurfaceHit& hit) {
  PathVertex v;
  v.kind = VertexKind::Surface;
  v.position = hit.position;
  v.normal = hit.geometric_normal;
  v.shading = hit.shading;
  v.uv = hit.uv;
  v.bsdf = hit.bsdf;
  v.light = hit.light;
  return v;
}

PathVertex make_environment_vertex(const Scene& scene, const Vec3& direction) {
  PathVertex v;
  v.kind = VertexKind::Environment;
  v.sky_direction = direction;
  v.light = scene.environment();
  return v;
}

}  // namespace emlt
