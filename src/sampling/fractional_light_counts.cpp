#include "emlt/sampling/fractional_light_counts.h"

#include <cmath>

#include "emlt/sampling/direct_lighting.h"

namespace emlt {

FractionalCount fractional_count(double expected, FractionalCountFault fault) {
  if (!(expected > 0.0)) return {};
  const double whole = std::floor(expected);
  const double fraction = expected - whole;
  if (fraction == 0.0) return {int(whole), 1.0};
  return {int(whole) + 1, fault == FractionalCountFault::LastSampleFullWeight ? 1.0 : fraction};
}

std::vector<LightTechnique> light_techniques(const Scene& scene, const EnvironmentSampling& env,
                                             FractionalCountFault fault) {
  std::vector<LightTechnique> techniques;
  const LightSet& lights = scene.lights();
  for (size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights.light(i);
    const double selection = double(lights.selection_probability(light));
    if (!(selection > 0.0)) continue;
    if (!(env.cube && &light == scene.environment())) {
      techniques.push_back({&light, -1, selection});
      continue;
    }
    const auto mu = cube_face_weights(*env.cube, env.receiver);
    for (int f = 0; f < CubeEnvironment::kFaces; ++f)
      if (mu[size_t(f)] > 0.0)
        techniques.push_back({&light, f,
                              fault == FractionalCountFault::CountFromFaceAlone
                                  ? mu[size_t(f)]
                                  : selection * mu[size_t(f)]});
  }
  return techniques;
}

Rgb light_samples_by_fractional_counts(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                       int samples, MisHeuristic heuristic,
                                       const EnvironmentSampling& env, DirectPointSet point_set,
                                       Rng& rng, FractionalCountFault fault) {
  if (scene.lights().empty() || hit.bsdf->is_purely_delta()) return Rgb(0.0f);
  Rgb total(0.0f);
  for (const LightTechnique& t : light_techniques(scene, env, fault)) {
    const FractionalCount count = fractional_count(t.probability * double(samples), fault);
    if (count.samples == 0) continue;
    const std::vector<Vec2> points = draw_direct_point_set(point_set, uint32_t(count.samples), rng);
    // The selection probability the one-sample estimator would report: with the face's
    // table density mu_f pdf(w | f) (sample_environment_face) it is the light's density.
    const float selection = scene.lights().selection_probability(*t.light);
    for (int i = 0; i < count.samples; ++i) {
      const Vec2 u = points.empty() ? rng.uniform2() : points[size_t(i)];
      const auto ls =
          t.face >= 0 ? sample_environment_face(*scene.environment(), env, hit.position, t.face, u)
                      : t.light->sample_direct(hit.position, u);
      const Rgb c = drawn_light_contribution(scene, hit, wo, TransportMode::Radiance, *t.light,
                                             selection, ls, heuristic);
      total += i + 1 == count.samples ? c * float(count.last_weight) : c;
    }
  }
  return total;
}

}  // namespace emlt
