#include "emlt/sampling/direct_sample.h"

namespace emlt {

ArrivingEmission arriving_emission(const Scene& scene, const Vec3& from, const Vec3& direction,
                                   const SurfaceHit* emitter_hit, bool with_pdf,
                                   const EnvironmentSampling& sampling) {
  const LightSet& lights = scene.lights();
  ArrivingEmission out;
  if (emitter_hit) {
    if (!emitter_hit->light) return out;
    out.radiance = emitter_hit->emitted(-direction);
    if (is_black(out.radiance)) return out;
    if (with_pdf)
      out.light_pdf = lights.selection_probability(*emitter_hit->light) *
                      emitter_hit->light->pdf_direct(from, emitter_hit->position,
                                                     emitter_hit->geometric_normal, direction);
  } else {
    const EnvironmentLight* environment = scene.environment();
    if (!environment) return out;
    out.radiance = environment->radiance(direction);
    if (with_pdf)
      out.light_pdf = lights.selection_probability(*environment) *
                      (sampling.cube ? environment_direct_pdf(*environment, sampling, direction)
                                     : environment->pdf_direction(direction));
  }
  return out;
}

DirectSample draw_light_direction(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                  float u_select, const Vec2& u_light,
                                  const EnvironmentSampling& env) {
  DirectSample out;
  const LightSet& lights = scene.lights();
  if (lights.empty() || hit.bsdf->is_purely_delta()) return out;
  float selection = 0.0f;
  const Light* light = lights.choose(u_select, &selection);
  if (!light || selection <= 0.0f) return out;
  const auto ls = env.cube && light == scene.environment()
                      ? sample_environment_direct(*scene.environment(), env, hit.position, u_light)
                      : light->sample_direct(hit.position, u_light);
  if (!ls || ls->pdf <= 0.0f || is_black(ls->radiance)) return out;
  out.own_pdf = selection * ls->pdf;
  out.delta = ls->delta;
  out.wi = ls->wi;

  const Vec3 wo_local = hit.shading.to_local(wo), wi_local = hit.shading.to_local(ls->wi);
  // Under strict normals light must not cross between the geometric and shading sides.
  if (!scene.sides_agree(hit.geometric_normal, ls->wi, wi_local.z) ||
      !scene.sides_agree(hit.geometric_normal, wo, wo_local.z))
    return out;
  const BsdfContext ctx{hit.uv, TransportMode::Radiance, hit.vertex_color};
  const Rgb f = hit.bsdf->eval(ctx, wo_local, wi_local);
  if (is_black(f)) return out;
  const bool unoccluded =
      light->at_infinity()
          ? !scene.occluded(spawn_ray(hit.position, hit.geometric_normal, ls->wi))
          : scene.visible(hit.position, hit.geometric_normal, ls->position, ls->normal);
  if (!unoccluded) return out;
  out.estimate = f * std::abs(wi_local.z) * ls->radiance / out.own_pdf;
  if (!out.delta) out.other_pdf = hit.bsdf->pdf(ctx, wo_local, wi_local);
  return out;
}

DirectSample draw_bsdf_direction(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                 float u_lobe, const Vec2& u_direction,
                                 const EnvironmentSampling& env) {
  DirectSample out;
  const Vec3 wo_local = hit.shading.to_local(wo);
  const BsdfContext ctx{hit.uv, TransportMode::Radiance, hit.vertex_color};
  const auto bs = hit.bsdf->sample(ctx, wo_local, u_lobe, u_direction);
  if (!bs || is_black(bs->weight) || !(bs->pdf > 0.0f)) return out;
  out.own_pdf = bs->pdf;
  out.delta = bs->is_delta();
  const Vec3 wi = hit.shading.to_world(bs->wi);
  out.wi = wi;
  if (!scene.sides_agree(hit.geometric_normal, wi, bs->wi.z)) return out;
  SurfaceHit next;
  const bool found = scene.intersect(spawn_ray(hit.position, hit.geometric_normal, wi), next);
  const ArrivingEmission e =
      arriving_emission(scene, hit.position, wi, found ? &next : nullptr, !out.delta, env);
  if (is_black(e.radiance)) return out;
  out.estimate = bs->weight * e.radiance;
  out.other_pdf = e.light_pdf;
  return out;
}

}  // namespace emlt
