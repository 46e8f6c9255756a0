#pragma once
// The path tracer's estimate of one camera ray, for any source of uniform numbers: the
// renderer's PCG streams (path_tracer.cpp), and primary-sample-space MLT's coordinates,
// whose concrete stream type (PrimaryStream, final) lets the compiler call its reads
// directly instead of through SampleSource's virtual function: some 20 coordinates are
// read per path, each a few instructions when it was read before in the iteration.
#include "emlt/sampling/direct_lighting.h"
#include "emlt/scene/scene.h"
#include "emlt/settings/settings.h"

namespace emlt {

// Paths of fewer than `min_segments` segments add nothing (PSSMLT with the direct light
// rendered separately); their samples are drawn all the same. With 1 it is the plain
// path tracer. `longest` (PSSMLT's statistics, may be null): the segments of the longest
// path that added light, 0 if none did.
template <class Sampler>
Rgb path_tracer_estimate(const Scene& scene, const RenderSettings& settings, const Ray& camera_ray,
                         Sampler& rng, int min_segments, int* longest) {
  Rgb result(0.0f), throughput(1.0f);
  Ray ray = camera_ray;
  Vec3 previous_position = ray.origin;
  float previous_pdf = 0.0f;
  bool previous_delta = true;  // emission seen straight from the camera is never MIS-weighted
  // How light sampling sampled the environment at the previous vertex (its pdf for a
  // BSDF-sampled ray that finds the sky depends on that vertex's normal under cube-balanced).
  EnvironmentSampling previous_env{};

  // Scene::intersect sets every field of a hit it finds, so one record serves the whole
  // path (constructing it afresh cost some 26 instructions a bounce, 1 % of a sample).
  SurfaceHit hit;
  // `segments` counts the path's edges so far; max_depth bounds it (Mitsuba's maxDepth).
  for (int segments = 1;; ++segments) {
    const bool found = scene.intersect(ray, hit);
    if (!found) {
      if (segments >= min_segments) {
        const Rgb light = throughput * weighted_emission(scene, previous_position, ray.direction,
                                                         nullptr, previous_pdf, previous_delta,
                                                         settings.mis, previous_env);
        result += light;
        if (longest && !is_black(light)) *longest = segments;
      }
      break;
    }
    if (hit.light && segments >= min_segments) {
      const Rgb light =
          throughput * weighted_emission(scene, previous_position, ray.direction, &hit,
                                         previous_pdf, previous_delta, settings.mis);
      result += light;
      if (longest && !is_black(light)) *longest = segments;
    }
    if (settings.max_depth >= 0 && segments >= settings.max_depth) break;

    const Vec3 wo = -ray.direction;
    // Under strict normals the path ends where the two normals disagree on its arrival
    // (Mitsuba's path tracer); the light sample below would be zero, the BSDF's not.
    const Vec3 wo_local = hit.shading.to_local(wo);
    if (!scene.sides_agree(hit.geometric_normal, wo, wo_local.z)) break;
    const float u_select = rng.uniform();
    const Vec2 u_light = rng.uniform2();
    const EnvironmentSampling env =
        settings.env_sampler == EnvSampler::LatLong
            ? EnvironmentSampling{}
            : environment_sampling(scene, settings.env_sampler, hit, wo, settings.env_face_balance,
                                   settings.env_cube_resolution);
    if (segments + 1 >= min_segments) {
      const Rgb light =
          throughput * sample_light_contribution(scene, hit, wo, TransportMode::Radiance, u_select,
                                                 u_light, settings.mis, env);
      result += light;
      if (longest && !is_black(light)) *longest = segments + 1;
    }

    const float u_lobe = rng.uniform();
    const auto bs = hit.bsdf->sample(BsdfContext{hit.uv, TransportMode::Radiance, hit.vertex_color},
                                     wo_local, u_lobe, rng.uniform2());
    if (!bs || is_black(bs->weight)) break;
    const Vec3 wi = hit.shading.to_world(bs->wi);
    // Under strict normals, a direction on the wrong side of the geometric surface would
    // leak light.
    if (!scene.sides_agree(hit.geometric_normal, wi, bs->wi.z)) break;
    throughput *= bs->weight;
    previous_position = hit.position;
    previous_pdf = bs->pdf;
    previous_delta = bs->is_delta();
    previous_env = env;
    ray = spawn_ray(hit.position, hit.geometric_normal, wi);

    if (segments >= settings.rr_depth) {
      const float survival = glm::min(max_component(throughput), 0.95f);
      if (rng.uniform() >= survival) break;
      throughput /= survival;
    }
  }
  return result;
}

}  // namespace emlt
