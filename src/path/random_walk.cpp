#include "emlt/path/random_walk.h"

#include "emlt/path/connection.h"

namespace emlt {

namespace {

bool keep_finite(Rgb& value, InvalidCounter* invalid) {
  InvalidCounter local;
  return (invalid ? *invalid : local).keep(value);
}

// The vertex a ray from `origin` along `direction` reaches: a surface, the sky, or nothing.
std::optional<PathVertex> trace_to_vertex(const Scene& scene, const Ray& ray) {
  SurfaceHit hit;
  if (scene.intersect(ray, hit)) return make_surface_vertex(hit);
  if (scene.environment()) return make_environment_vertex(scene, ray.direction);
  return std::nullopt;
}

template <class Sampler>
int walk(const Scene& scene, Sampler& rng, TransportMode mode, int steps, int rr_depth,
         PathVertices& subpath, InvalidCounter* invalid) {
  if (subpath.size() < 2) return 0;
  const bool importance = mode == TransportMode::Importance;
  int added = 0;
  while (added < steps) {
    const size_t index = subpath.size() - 1;  // also the subpath's segment count
    PathVertex& v = subpath[index];
    PathVertex& previous = subpath[index - 1];
    if (!v.is_surface() || !v.bsdf) break;

    // Both segments at v, each computed once for its direction and its density conversion.
    const Segment back = segment_between(v, previous);
    const Vec3& wo = back.w;
    const Vec3 wo_local = v.shading.to_local(wo);
    if (!scene.sides_agree(v.normal, wo, wo_local.z)) break;
    const float u_lobe = rng.uniform();
    const Vec2 u_direction = rng.uniform2();
    const auto bs =
        v.bsdf->sample(BsdfContext{v.uv, mode, v.vertex_color}, wo_local, u_lobe, u_direction);
    if (!bs || is_black(bs->weight) || !(bs->pdf > 0.0f)) break;
    const Vec3 wi = v.shading.to_world(bs->wi);
    if (!scene.sides_agree(v.normal, wi, bs->wi.z)) break;

    v.delta = bs->is_delta();

    // Russian roulette decides on the sampled estimate; survivors are divided by the
    // survival probability below. Survival follows the throughput relative to the
    // subpath's first vertex after the endpoint, so light subpaths (whose throughput
    // carries the emitted power) and camera subpaths are treated alike.
    float survival = 1.0f;
    if (rr_depth >= 0 && int(index) >= rr_depth) {
      const float reference = max_component(subpath[1].throughput);
      const Rgb estimate = v.throughput * bs->weight;
      survival = reference > 0.0f ? glm::min(max_component(estimate) / reference, 0.95f) : 0.0f;
      if (!(rng.uniform() < survival)) break;
    }

    auto next = trace_to_vertex(scene, spawn_ray(v.position, v.normal, wi));
    if (!next) break;

    // The ray left from an offset origin, so the segment v -> next is not exactly the
    // sampled direction. Densities and the throughput describe the vertex as it really
    // is: f/p of the real segment, in the radiance convention of vertex_factor (so a later
    // recomputation, a connection or MLT finds the same numbers).
    const Segment out = segment_between(v, *next);
    const Vec3& segment = out.w;
    const Vec3 segment_local = v.shading.to_local(segment);
    if (!scene.sides_agree(v.normal, segment, segment_local.z)) break;
    const float cos_wo_shading = std::abs(wo_local.z),
                cos_wo_geometric = std::abs(glm::dot(v.normal, wo));
    const float cos_segment_shading = std::abs(segment_local.z);
    const float cos_segment_geometric = std::abs(glm::dot(v.normal, segment));
    float forward_solid_angle = bs->pdf, reverse_solid_angle = bs->pdf_reverse;
    Rgb weight(0.0f);
    if (v.delta) {
      // Dirac lobe: f's factor is the sampled value with the light side's shading cosine
      // moved into it (Veach 1997 §5.3); its density is the lobe probability.
      // bs->eta = n(wi side) / n(wo side), 1 for a reflection (see vertex.h).
      const float crossing =
          dirac_crossing_factor(bs->eta, cos_wo_geometric, cos_segment_geometric);
      v.delta_probability = bs->pdf;
      v.delta_ior_ratio = glm::dot(v.normal, wi) > 0.0f ? bs->eta : 1.0f / bs->eta;
      v.delta_value = bs->value * crossing *
                      (importance ? cos_wo_shading / cos_wo_geometric
                                  : std::abs(bs->wi.z) / cos_segment_geometric);
      forward_solid_angle = bs->pdf * crossing;
      reverse_solid_angle = bs->pdf_reverse / crossing;
      weight = v.delta_value * (cos_segment_geometric / forward_solid_angle);
    } else {
      const BsdfContext context{v.uv, TransportMode::Radiance, v.vertex_color};
      forward_solid_angle = v.bsdf->pdf(context, wo_local, segment_local);
      reverse_solid_angle = v.bsdf->pdf(context, segment_local, wo_local);
      if (!(forward_solid_angle > 0.0f)) break;
      // Radiance walks: f(wo, wi) |wi.ns| / p. Importance walks use the adjoint, f with its
      // arguments swapped, times the shading-normal correction |wo.ns||wi.ng|/(|wo.ng||wi.ns|).
      weight = importance ? v.bsdf->eval(context, segment_local, wo_local) *
                                (cos_wo_shading * cos_segment_geometric /
                                 (cos_wo_geometric * forward_solid_angle))
                          : v.bsdf->eval(context, wo_local, segment_local) *
                                (cos_segment_shading / forward_solid_angle);
    }
    Rgb throughput = v.throughput * weight / survival;
    if (!keep_finite(throughput, invalid) || is_black(throughput)) break;
    next->throughput = throughput;
    const float forward = solid_angle_along(forward_solid_angle, *next, out);
    // The lens cannot be hit, so a camera vertex keeps pdf_from_light = 0.
    const float reverse =
        previous.is_camera() ? 0.0f : solid_angle_along(reverse_solid_angle, previous, back);
    (importance ? next->pdf_from_light : next->pdf_from_eye) = forward;
    (importance ? previous.pdf_from_eye : previous.pdf_from_light) = reverse;
    subpath.push_back(*next);  // invalidates v and previous
    ++added;
  }
  return added;
}

template <class Sampler>
int light_subpath(const Scene& scene, Sampler& rng, const WalkLimits& limits,
                  PathVertices& subpath, InvalidCounter* invalid) {
  subpath.clear();
  if (limits.max_vertices < 1) return 0;
  float selection = 0.0f;
  const Light* light = scene.lights().choose(rng.uniform(), &selection);
  const Vec2 u_position = rng.uniform2(), u_direction = rng.uniform2();
  if (!light || !(selection > 0.0f)) return 0;
  const auto emission = light->sample_emission(u_position, u_direction);
  if (!emission || !(emission->pdf_position > 0.0f) || !(emission->pdf_direction > 0.0f) ||
      is_black(emission->radiance))
    return 0;

  PathVertex origin;
  if (light->at_infinity()) {
    origin = make_environment_vertex(scene, -emission->ray.direction);
    if (light->is_delta_direction()) {
      origin.kind = VertexKind::DistantEmitter;
      origin.light = light;
    }
    origin.pdf_from_light = selection * emission->pdf_direction;
  } else if (light->is_delta_position()) {
    origin.kind = VertexKind::PointEmitter;
    origin.position = emission->ray.origin;
    origin.light = light;
    origin.pdf_from_light = selection * emission->pdf_position;
    // A beam (a point and a direction) emits through a Dirac lobe: no connection may end
    // at its vertex, as none may at a specular bounce.
    origin.delta = light->is_delta_direction();
  } else {
    origin.kind = VertexKind::Surface;
    origin.position = emission->ray.origin;
    origin.normal = emission->normal;
    origin.shading = Frame(emission->normal);
    origin.light = light;
    origin.pdf_from_light = selection * emission->pdf_position;
  }
  origin.throughput = Rgb(1.0f / origin.pdf_from_light);
  subpath.push_back(origin);
  if (limits.max_vertices < 2) return 1;

  auto first = trace_to_vertex(scene, emission->ray);
  if (!first || first->is_environment()) return 1;
  // Le |cos| / (p_select p_position p_direction): f/p of the first segment.
  // No cosine at the sky, a directional light or a point: none has a surface.
  const float cos_emission = light->at_infinity() || light->is_delta_position()
                                 ? 1.0f
                                 : std::abs(glm::dot(emission->normal, emission->ray.direction));
  Rgb throughput = emission->radiance *
                   (cos_emission / (selection * emission->pdf_position * emission->pdf_direction));
  if (!keep_finite(throughput, invalid) || is_black(throughput)) return 1;
  first->throughput = throughput;
  first->pdf_from_light =
      light->at_infinity()
          ? emission->pdf_position * abs_cos_at(*first, emission->ray.direction)
          : solid_angle_to_vertex_measure(emission->pdf_direction, origin, *first);
  subpath.push_back(*first);
  walk(scene, rng, TransportMode::Importance, limits.max_vertices - 2, limits.rr_depth,
              subpath, invalid);
  return int(subpath.size());
}

template <class Sampler>
int camera_subpath(const Scene& scene, Sampler& rng, const Vec2& raster, const Vec2& u_lens,
                   const WalkLimits& limits, PathVertices& subpath,
                   InvalidCounter* invalid) {
  subpath.clear();
  if (limits.max_vertices < 1) return 0;
  const Camera& camera = scene.camera();
  const Ray ray = camera.generate_ray(raster, u_lens);
  float pdf_position = 0.0f, pdf_direction = 0.0f;
  camera.pdf_emission(ray.direction, &pdf_position, &pdf_direction);
  if (!(pdf_position > 0.0f) || !(pdf_direction > 0.0f)) return 0;

  PathVertex lens = make_camera_vertex(scene, ray.origin, raster);
  lens.pdf_from_eye = pdf_position;
  lens.throughput = Rgb(1.0f / pdf_position);
  subpath.push_back(lens);
  if (limits.max_vertices < 2) return 1;

  auto first = trace_to_vertex(scene, ray);
  if (!first) return 1;
  // W_e |cos| / (p_position p_direction) is exactly 1 by the camera's normalisation
  // (camera.h), so the first vertex starts with unit throughput, as in the path tracer
  // (orthographic: W_e G = |cos| / A over the density |cos| / A).
  first->throughput = Rgb(1.0f);
  if (lens.kind == VertexKind::OrthographicCamera)
    first->pdf_from_eye = camera.orthographic_hit_density(
        abs_cos_at(*first, lens.normal), segment_between(lens, *first).distance_squared);
  else
    first->pdf_from_eye = solid_angle_to_vertex_measure(pdf_direction, lens, *first);
  subpath.push_back(*first);
  walk(scene, rng, TransportMode::Radiance, limits.max_vertices - 2, limits.rr_depth,
              subpath, invalid);
  return int(subpath.size());
}

}  // namespace

int random_walk(const Scene& scene, Rng& rng, TransportMode mode, int steps, int rr_depth,
                PathVertices& subpath, InvalidCounter* invalid) {
  return walk(scene, rng, mode, steps, rr_depth, subpath, invalid);
}
int random_walk(const Scene& scene, SampleSource& samples, TransportMode mode, int steps,
                int rr_depth, PathVertices& subpath, InvalidCounter* invalid) {
  return walk(scene, samples, mode, steps, rr_depth, subpath, invalid);
}
int generate_light_subpath(const Scene& scene, Rng& rng, const WalkLimits& limits,
                           PathVertices& subpath, InvalidCounter* invalid) {
  return light_subpath(scene, rng, limits, subpath, invalid);
}
int generate_light_subpath(const Scene& scene, SampleSource& samples, const WalkLimits& limits,
                           PathVertices& subpath, InvalidCounter* invalid) {
  return light_subpath(scene, samples, limits, subpath, invalid);
}
int generate_camera_subpath(const Scene& scene, Rng& rng, const Vec2& raster, const Vec2& u_lens,
                            const WalkLimits& limits, PathVertices& subpath,
                            InvalidCounter* invalid) {
  return camera_subpath(scene, rng, raster, u_lens, limits, subpath, invalid);
}
int generate_camera_subpath(const Scene& scene, SampleSource& samples, const Vec2& raster,
                            const Vec2& u_lens, const WalkLimits& limits,
                            PathVertices& subpath, InvalidCounter* invalid) {
  return camera_subpath(scene, samples, raster, u_lens, limits, subpath, invalid);
}

}  // namespace emlt
