#include "emlt/sampling/mixture_direct_estimator.h"

#include <algorithm>
#include <cmath>

#include "emlt/sampling/direct_sample.h"

namespace emlt {

namespace {

// A direction's contribution to the mixture estimate, `own_share` and `other_share` being
// the probabilities of choosing its strategy and the other one.
Rgb mixture_term(const DirectSample& s, double own_share, double other_share) {
  if (is_black(s.estimate)) return Rgb(0.0f);
  if (s.delta) return s.estimate / float(own_share);
  const double mixture = own_share * double(s.own_pdf) + other_share * double(s.other_pdf);
  return s.estimate * float(double(s.own_pdf) / mixture);
}

DirectSample draw_light(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, Rng& rng,
                        const EnvironmentSampling& env) {
  const float u_select = rng.uniform();
  return draw_light_direction(scene, hit, wo, u_select, rng.uniform2(), env);
}

DirectSample draw_bsdf(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, Rng& rng,
                       const EnvironmentSampling& env) {
  const float u_lobe = rng.uniform();
  return draw_bsdf_direction(scene, hit, wo, u_lobe, rng.uniform2(), env);
}

}  // namespace

double effective_light_share(const SurfaceHit& hit, double alpha) {
  return hit.bsdf->is_purely_delta() ? 0.0 : std::clamp(alpha, 0.0, 1.0);
}

Rgb estimate_direct_mixture(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, Rng& rng,
                            double alpha, int directions, const EnvironmentSampling& env) {
  const int n = std::max(directions, 1);
  const double a = effective_light_share(hit, alpha);
  const double offset = double(rng.uniform());
  Rgb total(0.0f);
  for (int i = 0; i < n; ++i) {
    const bool from_light = (double(i) + offset) / double(n) < a;
    total += from_light ? mixture_term(draw_light(scene, hit, wo, rng, env), a, 1.0 - a)
                        : mixture_term(draw_bsdf(scene, hit, wo, rng, env), 1.0 - a, a);
  }
  return total / float(n);
}

Rgb estimate_direct_pilot(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, Rng& rng,
                          int directions, SecondOrderAlpha* moments,
                          const EnvironmentSampling& env) {
  const int pairs = std::max(directions / 2, 1);
  Rgb total(0.0f);
  for (int i = 0; i < pairs; ++i) {
    // A light and a BSDF direction: together a stratified draw from pbar, so Eq. 5.5's
    // sums over them estimate the integrals of Eq. 5.4.
    const DirectSample light = draw_light(scene, hit, wo, rng, env);
    const DirectSample bsdf = draw_bsdf(scene, hit, wo, rng, env);
    total += mixture_term(light, 0.5, 0.5) + mixture_term(bsdf, 0.5, 0.5);
    if (!moments) continue;
    if (!light.delta && !is_black(light.estimate))
      moments->add(double(luminance(light.integrand())), light.own_pdf, light.other_pdf);
    if (!bsdf.delta && !is_black(bsdf.estimate))
      moments->add(double(luminance(bsdf.integrand())), bsdf.other_pdf, bsdf.own_pdf);
  }
  return total / float(2 * pairs);
}

Rgb estimate_direct_second_order(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                 Rng& rng, int directions, const SecondOrderSplit& split,
                                 double* alpha_used, const EnvironmentSampling& env) {
  const int total = std::max(directions, 2);
  // Light sampling never finds anything a purely specular BSDF reflects: a pilot would spend
  // half its directions on nothing and learn nothing (Dirac draws stay out of Eq. 5.5).
  if (hit.bsdf->is_purely_delta()) {
    if (alpha_used) *alpha_used = 0.0;
    return estimate_direct_mixture(scene, hit, wo, rng, 0.0, total, env);
  }
  const int pilot =
      std::clamp(2 * int(std::lround(0.5 * split.pilot * double(total))), 2, total - total % 2);
  const int rest = total - pilot;
  SecondOrderAlpha moments;
  const Rgb first = estimate_direct_pilot(scene, hit, wo, rng, pilot, &moments, env);
  const double alpha = moments.alpha(split.clamp);
  if (alpha_used) *alpha_used = alpha;
  if (rest == 0) return first;
  const Rgb second = estimate_direct_mixture(scene, hit, wo, rng, alpha, rest, env);
  // Eq. 5.6: each part weighted by its share of the directions.
  return (first * float(pilot) + second * float(rest)) / float(total);
}

}  // namespace emlt
