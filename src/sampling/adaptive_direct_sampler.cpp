#include "emlt/sampling/adaptive_direct_sampler.h"

#include <algorithm>
#include <cmath>

#include "emlt/sampling/direct_sample.h"

namespace emlt {

namespace {

constexpr double kPiD = 3.14159265358979323846;

// The step of the central difference that stands for the paper's analytic derivatives
// (sections 4.4-4.5): far below any cell the refinement makes in practice, far above
// float directions' resolution. On a lat-long map it gives the slope of the bilinear
// interpolation the environment evaluates.
constexpr double kDerivativeStep = 1e-4;

bool consistent_sides(const Scene& scene, const SurfaceHit& hit, const Vec3& w_world,
                      const Vec3& w_local) {
  return scene.sides_agree(hit.geometric_normal, w_world, w_local.z);
}

}  // namespace

Vec3 AdaptiveDirectionMap::direction(const std::array<double, 2>& u) const {
  const double phi = 2.0 * kPiD * u[0];
  if (parametrisation_ == AdaptiveParametrisation::Global) {
    const double theta = kPiD * u[1];
    // World axes: i = +x, j = +z, k = +y (the engine's up).
    return glm::normalize(Vec3(float(std::cos(phi) * std::sin(theta)), float(std::cos(theta)),
                               float(std::sin(phi) * std::sin(theta))));
  }
  const double r = std::sqrt(u[1]), z = std::sqrt(std::max(0.0, 1.0 - u[1]));
  return glm::normalize(
      frame_.to_world(Vec3(float(std::cos(phi) * r), float(std::sin(phi) * r), float(z))));
}

double AdaptiveDirectionMap::jacobian(const std::array<double, 2>& u) const {
  if (parametrisation_ == AdaptiveParametrisation::Global)
    return 2.0 * kPiD * kPiD * std::sin(kPiD * u[1]);
  const double cosine = std::sqrt(std::max(0.0, 1.0 - u[1]));
  return cosine > 0.0 ? kPiD / cosine : 0.0;
}

Rgb estimate_direct_adaptive(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, Rng& rng,
                             const AdaptiveDirectOptions& options, AdaptiveDirectTrace* trace) {
  const Vec3 wo_local = hit.shading.to_local(wo);
  const BsdfContext ctx{hit.uv, TransportMode::Radiance, hit.vertex_color};
  // The cosine map covers the hemisphere light is reflected from, about the shading normal
  // turned to wo's side.
  Frame frame = hit.shading;
  if (wo_local.z < 0.0f) {
    frame.n = -frame.n;
    frame.t = -frame.t;
  }
  const AdaptiveDirectionMap map(options.parametrisation, frame);
  const EnvironmentLight* environment = scene.environment();

  // The reflection factor R = f_s |cos| dw/du at u (section 4), and its direction.
  struct Reflection {
    Vec3 w{0.0f};
    Rgb factor{0.0f};
  };
  const auto reflection = [&](const std::array<double, 2>& u) {
    Reflection r;
    r.w = map.direction(u);
    const double jacobian = map.jacobian(u);
    const Vec3 wi_local = hit.shading.to_local(r.w);
    if (!(jacobian > 0.0) || !consistent_sides(scene, hit, r.w, wi_local)) return r;
    r.factor = hit.bsdf->eval(ctx, wo_local, wi_local) * float(std::abs(wi_local.z) * jacobian);
    return r;
  };
  // The integrand without visibility (section 3.3: the derivative leaves it out) and without
  // area lights, whose radiance is constant but for its edges: L_env R.
  const auto unoccluded = [&](const std::array<double, 2>& u) {
    if (!environment) return 0.0;
    const Reflection r = reflection(u);
    if (is_black(r.factor)) return 0.0;
    return double(luminance(r.factor * environment->radiance(r.w)));
  };

  std::vector<Rgb> values;
  values.reserve(size_t(std::max(options.budget, 1)));
  if (trace) trace->directions.clear();
  const auto evaluate = [&](size_t, const std::array<double, 2>& u) {
    CellSample s;
    const Reflection r = reflection(u);
    Rgb value(0.0f);
    if (!is_black(r.factor)) {
      SurfaceHit next;
      const bool found = scene.intersect(spawn_ray(hit.position, hit.geometric_normal, r.w), next);
      value = r.factor *
              arriving_emission(scene, hit.position, r.w, found ? &next : nullptr, false).radiance;
    }
    values.push_back(value);
    if (trace) trace->directions.push_back(r.w);
    s.value = luminance(value);
    // Equal cells only (`initial` covers the budget): the slopes would never be read.
    for (int axis = 0; axis < 2 && options.initial < options.budget; ++axis) {
      std::array<double, 2> lo = u, hi = u;
      lo[size_t(axis)] = std::max(0.0, u[size_t(axis)] - kDerivativeStep);
      hi[size_t(axis)] = std::min(1.0 - 1e-12, u[size_t(axis)] + kDerivativeStep);
      s.slope[size_t(axis)] =
          std::abs(unoccluded(hi) - unoccluded(lo)) / (hi[size_t(axis)] - lo[size_t(axis)]);
    }
    return s;
  };

  // The paper's random initial index: decorrelates neighbouring shading points while each
  // keeps the whole cell structure.
  const uint64_t first = rng.next_u32();
  const std::vector<AdaptiveLeaf> leaves = refine_adaptively(
      first, AdaptiveQuadratureOptions{options.budget, options.initial, options.robustness},
      evaluate);

  // Eq. 3: each point's value times its cell's area.
  Rgb total(0.0f);
  for (const AdaptiveLeaf& leaf : leaves) total += values[leaf.point] * float(leaf.cell.area());

  // Delta lights: exactly, one shadow ray each.
  for (size_t i = 0; i < scene.lights().size(); ++i) {
    const Light& light = scene.lights().light(i);
    if (!light.is_delta()) continue;
    const auto ls = light.sample_direct(hit.position, Vec2(0.5f));
    if (!ls || is_black(ls->radiance)) continue;
    const Vec3 wi_local = hit.shading.to_local(ls->wi);
    if (!consistent_sides(scene, hit, ls->wi, wi_local)) continue;
    const Rgb f = hit.bsdf->eval(ctx, wo_local, wi_local);
    if (is_black(f)) continue;
    const bool unoccluded_light =
        light.at_infinity()
            ? !scene.occluded(spawn_ray(hit.position, hit.geometric_normal, ls->wi))
            : scene.visible(hit.position, hit.geometric_normal, ls->position, ls->normal);
    if (unoccluded_light) total += f * std::abs(wi_local.z) * ls->radiance / ls->pdf;
  }
  if (trace) {
    trace->leaves = leaves;
    trace->values = values;
  }
  return total;
}

}  // namespace emlt
