#include "mutations/perturbation_common.h"

#include <cmath>

#include "emlt/core/warp.h"

namespace emlt::perturbation {

namespace {

// Lobe numbers tried, in order, to reach a delta lobe of the wanted kind. The project's
// BSDFs put specular reflection below a threshold of u_lobe and transmission above it.
constexpr float kLobeProbes[] = {0.0f, 0x1.fffffep-1f, 0.5f, 0.25f, 0.75f};

std::optional<BsdfSample> sample_delta_lobe(const PathVertex& v, const Vec3& wo_local,
                                            TransportMode mode, bool transmission) {
  if (!v.is_surface() || !v.bsdf || !v.bsdf->has_delta_lobe()) return std::nullopt;
  const BsdfContext context{v.uv, mode};
  for (const float u_lobe : kLobeProbes) {
    const auto s = v.bsdf->sample(context, wo_local, u_lobe, Vec2(0.5f));
    if (!s || !s->is_delta() || !(s->pdf > 0.0f)) continue;
    if (((s->lobe & kLobeTransmission) != 0) != transmission) continue;
    return s;
  }
  return std::nullopt;
}

bool consistent_side(const PathVertex& v, const Vec3& w_world, const Vec3& w_local) {
  return glm::dot(v.normal, w_world) * w_local.z > 0.0f;
}

}  // namespace

Vec2 sample_image_offset(float r_min, float r_max, const Vec2& u) {
  const float radius = r_max * std::exp(-std::log(r_max / r_min) * u.x);
  return radius * unit_circle_point(u.y);
}

Vec3 perturb_direction(const Vec3& w, double theta_min, double theta_max, const Vec2& u) {
  const double theta = theta_max * std::exp(-std::log(theta_max / theta_min) * double(u.x));
  const double phi = 2.0 * M_PI * double(u.y);
  const Frame frame(w);
  const double sin_theta = std::sin(theta);
  // In double: at θ ~ 1e-4 the offset is near float's resolution of a unit vector.
  const DVec3 s(frame.s), t(frame.t), n(w);
  const DVec3 d = std::cos(theta) * n + sin_theta * (std::cos(phi) * s + std::sin(phi) * t);
  return Vec3(glm::normalize(d));
}

double angle_between(const DVec3& a, const DVec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

DVec3 precise_direction(const PathVertex& from, const PathVertex& to) {
  if (to.is_environment()) return DVec3(to.sky_direction);
  if (from.is_environment()) return -DVec3(from.sky_direction);
  return glm::normalize(DVec3(to.position) - DVec3(from.position));
}

bool crosses_surface(const PathVertex& v, const PathVertex& a, const PathVertex& b) {
  return glm::dot(v.normal, direction_between(v, a)) * glm::dot(v.normal, direction_between(v, b)) < 0.0f;
}

std::optional<PathVertex> trace_surface(const Scene& scene, const Ray& ray) {
  SurfaceHit hit;
  if (!scene.intersect(ray, hit)) return std::nullopt;
  PathVertex v = make_surface_vertex(hit);
  if (!v.bsdf) return std::nullopt;
  return v;
}

std::optional<Vec3> continue_through_delta(const PathVertex& v, const Vec3& w_back,
                                           TransportMode mode, bool transmission, float* eta) {
  const Vec3 wo_local = v.shading.to_local(w_back);
  if (!consistent_side(v, w_back, wo_local)) return std::nullopt;
  const auto s = sample_delta_lobe(v, wo_local, mode, transmission);
  if (!s) return std::nullopt;
  const Vec3 wi = glm::normalize(v.shading.to_world(s->wi));
  if (!consistent_side(v, wi, s->wi)) return std::nullopt;
  if (eta) *eta = s->eta;
  return wi;
}

bool fill_delta_record(PathVertex& v, const PathVertex& eye, const PathVertex& light,
                       TransportMode mode, bool transmission) {
  const bool importance = mode == TransportMode::Importance;
  // The walk arrives from the eye (radiance) or from the light (importance).
  const Vec3 w_back = direction_between(v, importance ? light : eye);
  const Vec3 wo_local = v.shading.to_local(w_back);
  if (!consistent_side(v, w_back, wo_local)) return false;
  const auto s = sample_delta_lobe(v, wo_local, mode, transmission);
  if (!s) return false;
  const Vec3 wi = v.shading.to_world(s->wi);
  // random_walk's formulas (vertex.h): the light side's shading cosine moved into the value,
  // the value rescaled by the crossing factor into the side-symmetric convention.
  const Vec3 w_light = direction_between(v, light);
  const float cos_light_geometric = std::abs(glm::dot(v.normal, w_light));
  if (!(cos_light_geometric > 0.0f)) return false;
  const float shading_correction =
      (importance ? std::abs(wo_local.z) : std::abs(s->wi.z)) / cos_light_geometric;
  const float crossing = dirac_crossing_factor(s->eta, std::abs(glm::dot(v.normal, w_back)),
                                               std::abs(glm::dot(v.normal, wi)));
  v.delta = true;
  v.delta_probability = s->pdf;
  v.delta_ior_ratio = glm::dot(v.normal, wi) > 0.0f ? s->eta : 1.0f / s->eta;
  v.delta_value = s->value * (crossing * shading_correction);
  return is_finite(v.delta_value) && !is_black(v.delta_value);
}

double log_convention_correction(const Path& x, int first, int last, TransportMode mode) {
  const auto& v = x.vertices;
  double correction = 0.0;
  for (int i = first; i <= last; ++i) {
    const PathVertex& stored = v[size_t(i)];
    if (!stored.delta) continue;
    PathVertex recomputed = stored;
    const PathVertex &eye = v[size_t(i + 1)], &light = v[size_t(i - 1)];
    if (!fill_delta_record(recomputed, eye, light, mode, crosses_surface(stored, eye, light)))
      continue;
    const double before = double(stored.delta_value.x) + stored.delta_value.y + stored.delta_value.z;
    const double after =
        double(recomputed.delta_value.x) + recomputed.delta_value.y + recomputed.delta_value.z;
    if (before > 0.0 && after > 0.0) correction += std::log(after / before);
  }
  return correction;
}

double eye_side_log_ratio(const Path& x, const Path& y, int l, bool include_jacobian) {
  const double log_jacobians =
      include_jacobian ? log_eye_jacobian(x, l + 1) - log_eye_jacobian(y, l + 1) : 0.0;
  return log_jacobians - log_convention_correction(x, l + 2, x.edges() - 1, TransportMode::Radiance);
}

double log_eye_jacobian(const Path& path, int first) {
  const auto& v = path.vertices;
  const int k = path.edges();
  double log_jacobian = 0.0;
  for (int i = first; i <= k - 1; ++i) {
    const PathVertex &z = v[size_t(i)], &eye_side = v[size_t(i + 1)];
    double factor = 0.0;
    if (i + 1 == k)
      factor = double(z.pdf_from_eye);  // camera: raster -> direction -> area
    else if (eye_side.delta)
      factor = double(z.pdf_from_eye) / double(eye_side.delta_probability);
    else
      factor = double(solid_angle_to_vertex_measure(1.0f, eye_side, z));  // perturbed direction
    log_jacobian += std::log(factor);
  }
  return log_jacobian;
}

double log_light_jacobian(const Path& path, int first, int last) {
  const auto& v = path.vertices;
  double log_jacobian = 0.0;
  for (int i = first; i <= last; ++i) {
    const PathVertex &z = v[size_t(i)], &light_side = v[size_t(i - 1)];
    const double factor = i == first || !light_side.delta
                              ? double(solid_angle_to_vertex_measure(1.0f, light_side, z))
                              : double(z.pdf_from_light) / double(light_side.delta_probability);
    log_jacobian += std::log(factor);
  }
  return log_jacobian;
}

double radians_per_pixel(const Camera& camera) { return camera.radians_per_pixel(); }

bool on_film(const Camera& camera, const Vec2& raster) {
  return raster.x >= 0.0f && raster.y >= 0.0f && raster.x < float(camera.width()) &&
         raster.y < float(camera.height());
}

bool aim_lens_at(const Scene& scene, PathVertex& lens, const PathVertex& seen) {
  if (lens.kind == VertexKind::OrthographicCamera) {
    if (seen.is_environment()) return false;
    const auto film = scene.camera().sample_direct(seen.position, Vec2(0.5f));
    if (!film) return false;
    lens.position = film->lens_point;
    lens.raster = film->raster;
    return true;
  }
  const auto raster = scene.camera().raster_position(lens.position, direction_between(lens, seen));
  if (!raster) return false;
  lens.raster = *raster;
  return true;
}

bool finish_proposal(const Scene& scene, const Path& x, Path& y) {
  return finish_proposal(scene, x, y, 0, int(y.vertices.size()) - 1);
}

bool finish_proposal(const Scene& scene, const Path& x, Path& y, int first, int last) {
  auto& v = y.vertices;
  if (v.size() != x.vertices.size() || v.size() < 2) return false;
  if (!v.front().is_emitter() || !v.back().is_camera()) return false;
  for (size_t i = 1; i + 1 < v.size(); ++i)
    if (!v[i].is_surface()) return false;
  y.type = compute_path_type(v);
  if (!(y.type == x.type)) return false;
  recompute_densities(scene, y, first, last);
  return true;
}

bool rebuild_eye_side(const Scene& scene, const Path& x, int l, const Vec2& raster,
                      const InteriorDirection& interior_direction, Path& y) {
  const auto& xv = x.vertices;
  const int k = x.edges();
  // l = -1: the walk ends on the light itself (x_0 on an emitting surface), no connection.
  if (l < -1 || l + 1 > k - 1) return false;
  if (l == -1 && !(xv.front().is_surface() && xv.front().is_emitter())) return false;
  const Camera& camera = scene.camera();
  if (!on_film(camera, raster)) return false;
  y = x;
  auto& yv = y.vertices;
  yv.back().raster = raster;
  Ray ray = camera.generate_ray_from_lens_point(raster, xv.back().position);
  // An orthographic camera's film point moves with the image point (camera.h).
  if (yv.back().kind == VertexKind::OrthographicCamera) yv.back().position = ray.origin;
  for (int i = k - 1; i >= l + 1; --i) {
    auto hit = trace_surface(scene, ray);
    if (!hit) return false;
    hit->throughput = xv[size_t(i)].throughput;  // not used by MLT; keeps the record complete
    if (i == 0 && !hit->is_emitter()) return false;
    yv[size_t(i)] = *hit;
    if (i == l + 1) break;
    const Vec3 w_back = direction_between(yv[size_t(i)], yv[size_t(i + 1)]);
    std::optional<Vec3> next;
    if (xv[size_t(i)].delta) {
      const bool transmission = crosses_surface(xv[size_t(i)], xv[size_t(i + 1)], xv[size_t(i - 1)]);
      next = continue_through_delta(yv[size_t(i)], w_back, TransportMode::Radiance, transmission);
    } else {
      if (!interior_direction) return false;
      next = interior_direction(i, direction_between(xv[size_t(i)], xv[size_t(i - 1)]));
    }
    if (!next) return false;
    ray = spawn_ray(yv[size_t(i)].position, yv[size_t(i)].normal, *next);
  }
  for (int i = l + 2; i <= k - 1; ++i) {
    if (!xv[size_t(i)].delta) continue;
    const bool transmission = crosses_surface(xv[size_t(i)], xv[size_t(i + 1)], xv[size_t(i - 1)]);
    if (!fill_delta_record(yv[size_t(i)], yv[size_t(i + 1)], yv[size_t(i - 1)],
                           TransportMode::Radiance, transmission))
      return false;
  }
  if (l >= 0) {
    const Rgb connection = connect_vertices(scene, l >= 1 ? &yv[size_t(l - 1)] : nullptr,
                                            yv[size_t(l)], yv[size_t(l + 1)], &yv[size_t(l + 2)]);
    if (is_black(connection) || !is_finite(connection)) return false;
  }
  // The lens point moved only its raster (an orthographic film point moved too, but its
  // own densities do not depend on where: finish_proposal recomputes x_{k-1}'s from it).
  return finish_proposal(scene, x, y, l + 1, k - 1);
}

}  // namespace emlt::perturbation
