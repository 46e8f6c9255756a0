#include "emlt/path/connection.h"

namespace emlt {

namespace {

// Under strict normals the geometric and the shading normal must put w on the same side;
// otherwise an interpolated normal would let light through the surface.
bool consistent_side(const Scene& scene, const PathVertex& v, const Vec3& w_world,
                     const Vec3& w_local) {
  return scene.sides_agree(v.normal, w_world, w_local.z);
}

// Surfaces are offset along their normal for shadow rays; lens points are not.
Vec3 offset_normal(const PathVertex& v) {
  return v.is_camera() ? Vec3(0.0f) : v.normal;
}

}  // namespace

namespace {

// vertex_factor without the Dirac shortcut: what a connection ending at v evaluates, since
// the lobe a walk sampled at v to continue plays no part in a path that ends there.
Rgb smooth_factor_along(const Scene& scene, const PathVertex& v, const Vec3* w_light,
                        const Vec3* w_eye) {
  if (!w_light) {  // x0: the emitter's radiance towards the rest of the path
    if (!w_eye || !v.light) return Rgb(0.0f);
    if (v.is_environment()) return v.light->emitted(Vec3(0.0f), v.sky_direction);
    return v.light->emitted(v.normal, *w_eye);
  }
  if (!w_eye) {  // xk: the camera's importance towards the rest of the path
    if (!v.is_camera()) return Rgb(0.0f);
    return Rgb(scene.camera().importance(v.position, *w_light));
  }
  if (!v.is_surface() || !v.bsdf) return Rgb(0.0f);
  const Vec3 eye_local = v.shading.to_local(*w_eye), light_local = v.shading.to_local(*w_light);
  if (!consistent_side(scene, v, *w_eye, eye_local) ||
      !consistent_side(scene, v, *w_light, light_local))
    return Rgb(0.0f);
  const float cos_geometric = std::abs(glm::dot(v.normal, *w_light));
  if (!(cos_geometric > 0.0f)) return Rgb(0.0f);
  const Rgb f = v.bsdf->eval(BsdfContext{v.uv, TransportMode::Radiance, v.vertex_color}, eye_local,
                             light_local);
  return f * (std::abs(light_local.z) / cos_geometric);
}

Rgb smooth_vertex_factor(const Scene& scene, const PathVertex& v, const PathVertex* light_side,
                         const PathVertex* eye_side) {
  // Directions only where they are used: an emitter or lens end looks one way.
  const bool interior = light_side && eye_side;
  Vec3 w_light(0.0f), w_eye(0.0f);
  if (light_side && (interior || v.is_camera())) w_light = direction_between(v, *light_side);
  if (eye_side && (interior || (v.light && !v.is_environment())))
    w_eye = direction_between(v, *eye_side);
  return smooth_factor_along(scene, v, light_side ? &w_light : nullptr,
                             eye_side ? &w_eye : nullptr);
}

}  // namespace

Rgb vertex_factor(const Scene& scene, const PathVertex& v, const PathVertex* light_side,
                  const PathVertex* eye_side) {
  if (light_side && eye_side && v.delta) return v.delta_value;
  return smooth_vertex_factor(scene, v, light_side, eye_side);
}

Rgb vertex_factor_along(const Scene& scene, const PathVertex& v, const Vec3* w_light,
                        const Vec3* w_eye) {
  if (w_light && w_eye && v.delta) return v.delta_value;
  return smooth_factor_along(scene, v, w_light, w_eye);
}

bool mutually_visible(const Scene& scene, const PathVertex& a, const PathVertex& b) {
  if (a.is_environment() && b.is_environment()) return false;
  if (a.is_environment() || b.is_environment()) {
    const PathVertex& finite = a.is_environment() ? b : a;
    const PathVertex& sky = a.is_environment() ? a : b;
    return !scene.occluded(spawn_ray(finite.position, offset_normal(finite), sky.sky_direction));
  }
  return scene.visible(a.position, offset_normal(a), b.position, offset_normal(b));
}

Rgb connect_vertices(const Scene& scene, const PathVertex* y_prev, const PathVertex& y,
                     const PathVertex& z, const PathVertex* z_prev) {
  // The sky ends a path on the light side only; an escaped eye ray cannot scatter.
  if (z.is_environment() || (y.is_environment() && y_prev)) return Rgb(0.0f);
  // A delta light seen straight from the lens: Mitsuba draws no point or directional light
  // in the image, and no other strategy could sample this path.
  if (!y_prev && y.is_delta_emitter() && z.is_camera()) return Rgb(0.0f);
  // An orthographic camera sees the sky in its one direction, which no sampled sky
  // direction is (the camera walk finds it instead).
  if (y.is_environment() && z.kind == VertexKind::OrthographicCamera) return Rgb(0.0f);
  // Purely specular surfaces are never connected (their eval is zero anyway: skip early).
  const auto purely_delta = [](const PathVertex& v) { return v.bsdf && v.bsdf->is_purely_delta(); };
  if ((y_prev && purely_delta(y)) || (z_prev && purely_delta(z))) return Rgb(0.0f);
  // The connecting segment serves both ends and G (its reverse is exactly -w).
  const Segment yz = segment_between(y, z);
  const Vec3 zy = -yz.w;
  const Vec3 y_back = y_prev ? direction_between(y, *y_prev) : Vec3(0.0f);
  const Rgb f_light_end = smooth_factor_along(scene, y, y_prev ? &y_back : nullptr, &yz.w);
  if (is_black(f_light_end)) return Rgb(0.0f);
  const Vec3 z_back = z_prev ? direction_between(z, *z_prev) : Vec3(0.0f);
  const Rgb f_eye_end = smooth_factor_along(scene, z, &zy, z_prev ? &z_back : nullptr);
  if (is_black(f_eye_end)) return Rgb(0.0f);
  const float g = geometry_term_along(y, z, yz);
  if (!(g > 0.0f)) return Rgb(0.0f);
  // Visibility last: it is the expensive part.
  if (!mutually_visible(scene, y, z)) return Rgb(0.0f);
  return f_light_end * g * f_eye_end;
}

namespace {

// pdf_towards_along; `smooth`: `from` evaluated by its smooth lobes even if a walk went on
// from it through a Dirac lobe (a connection end).
float pdf_along(const Scene& scene, const PathVertex* before, const PathVertex& from,
                const PathVertex& to, const Segment& out, const Vec3* back, bool smooth) {
  // No walk can hit the lens or a delta light.
  if (to.is_camera() || to.is_delta_emitter()) return 0.0f;
  const Vec3& w = out.w;
  if (from.is_camera()) {
    float pdf_position = 0.0f, pdf_direction = 0.0f;
    scene.camera().pdf_emission(w, &pdf_position, &pdf_direction);
    // Parallel rays: the film's density on the area they cross at `to` (camera.h).
    if (from.kind == VertexKind::OrthographicCamera)
      return pdf_direction > 0.0f ? scene.camera().orthographic_hit_density(
                                        abs_cos_at(to, from.normal), out.distance_squared)
                                  : 0.0f;
    return solid_angle_along(pdf_direction, to, out);
  }
  if (!before) {  // `from` is x0: its emission distribution
    if (!from.light || to.is_environment()) return 0.0f;
    float pdf_position = 0.0f, pdf_direction = 0.0f;
    from.light->pdf_emission(from.position, from.normal, w, &pdf_position, &pdf_direction);
    // The sky's rays start on a disk facing w: the receiving point's area projects onto it.
    if (from.is_environment()) return pdf_position * abs_cos_at(to, w);
    return solid_angle_along(pdf_direction, to, out);
  }
  if (!from.is_surface() || !from.bsdf) return 0.0f;
  const Vec3& w_before = *back;
  float pdf = 0.0f;
  if (from.delta && !smooth) {
    // Crossing from side a (towards `before`) to side b (towards `to`): the density carries
    // the crossing factor g(a -> b) (vertex.h).
    const auto ior = [&](const Vec3& dir) {
      return glm::dot(from.normal, dir) > 0.0f ? from.delta_ior_ratio : 1.0f;
    };
    pdf = from.delta_probability * dirac_crossing_factor(ior(w) / ior(w_before),
                                                         std::abs(glm::dot(from.normal, w_before)),
                                                         std::abs(glm::dot(from.normal, w)));
  } else {
    const Vec3 before_local = from.shading.to_local(w_before), to_local = from.shading.to_local(w);
    if (!consistent_side(scene, from, w_before, before_local) ||
        !consistent_side(scene, from, w, to_local))
      return 0.0f;
    pdf = from.bsdf->pdf(BsdfContext{from.uv, TransportMode::Radiance, from.vertex_color},
                         before_local, to_local);
  }
  return solid_angle_along(pdf, to, out);
}

}  // namespace

float pdf_towards_along(const Scene& scene, const PathVertex* before, const PathVertex& from,
                        const PathVertex& to, const Segment& out, const Vec3* back) {
  return pdf_along(scene, before, from, to, out, back, false);
}

float smooth_pdf_towards_along(const Scene& scene, const PathVertex* before, const PathVertex& from,
                               const PathVertex& to, const Segment& out, const Vec3* back) {
  return pdf_along(scene, before, from, to, out, back, true);
}

float pdf_towards(const Scene& scene, const PathVertex* before, const PathVertex& from,
                  const PathVertex& to) {
  if (to.is_camera()) return 0.0f;
  const Segment out = segment_between(from, to);
  const Vec3 back = before ? direction_between(from, *before) : Vec3(0.0f);
  return pdf_towards_along(scene, before, from, to, out, before ? &back : nullptr);
}

float pdf_light_origin(const Scene& scene, const PathVertex& v) {
  if (!v.light) return 0.0f;
  const float selection = scene.lights().selection_probability(*v.light);
  // A delta light's one point or direction: a discrete choice, probability 1.
  if (v.is_delta_emitter()) return selection;
  if (v.is_environment()) {
    return selection *
           static_cast<const EnvironmentLight*>(v.light)->pdf_direction(v.sky_direction);
  }
  float pdf_position = 0.0f;
  v.light->pdf_emission(v.position, v.normal, v.normal, &pdf_position, nullptr);
  return selection * pdf_position;
}

std::optional<PathVertex> sample_camera_vertex(const Scene& scene, const PathVertex& y,
                                               const Vec2& u_lens) {
  // A lens point seeing the sky directly is the camera path's job (s = 0); light tracing
  // from a sky direction is not implemented, and the MIS weights know it (path_density.h).
  if (y.is_environment()) return std::nullopt;
  const Camera& camera = scene.camera();
  const auto sample = camera.sample_direct(y.position, u_lens);
  if (!sample) return std::nullopt;
  PathVertex c = make_camera_vertex(scene, sample->lens_point, sample->raster);
  float pdf_position = 0.0f, pdf_direction = 0.0f;
  camera.pdf_emission(-sample->wi, &pdf_position, &pdf_direction);
  if (!(pdf_position > 0.0f)) return std::nullopt;
  c.pdf_from_eye = pdf_position;
  c.throughput = Rgb(1.0f / pdf_position);
  return c;
}

}  // namespace emlt
