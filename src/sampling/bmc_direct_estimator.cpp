#include "emlt/sampling/bmc_direct_estimator.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <tuple>

#include "emlt/core/error.h"
#include "emlt/core/gauss_legendre.h"
#include "emlt/sampling/direct_sample.h"

namespace emlt {

namespace {

constexpr double kPiD = 3.14159265358979323846;
constexpr int kPanelNodes = 16;

const GaussLegendreRule& panel_rule() {
  static const GaussLegendreRule rule = gauss_legendre(kPanelNodes);
  return rule;
}

// ∫_a^b e^{κ(t−1)} dt and ∫_a^b t e^{κ(t−1)} dt.
double exp_integral(double kappa, double a, double b) {
  return (std::exp(kappa * (b - 1.0)) - std::exp(kappa * (a - 1.0))) / kappa;
}
double t_exp_integral(double kappa, double a, double b) {
  const auto antiderivative = [&](double t) {
    return std::exp(kappa * (t - 1.0)) * (t / kappa - 1.0 / (kappa * kappa));
  };
  return antiderivative(b) - antiderivative(a);
}

// An orthonormal frame about a unit z axis (Duff et al.'s branchless construction).
struct FrameD {
  Vec3d s, t, n;
  explicit FrameD(const Vec3d& axis) : n(axis) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
    s = Vec3d(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = Vec3d(b, sign + n.y * n.y * a, -n.y);
  }
  Vec3d to_world(const Vec3d& w) const { return w.x * s + w.y * t + w.z * n; }
};

// In-place Cholesky factorisation and inverse of a symmetric positive definite matrix.
std::vector<double> spd_inverse(std::vector<double> a, int n) {
  for (int j = 0; j < n; ++j) {
    double d = a[size_t(j) * n + j];
    for (int k = 0; k < j; ++k) d -= a[size_t(j) * n + k] * a[size_t(j) * n + k];
    if (!(d > 0.0)) throw Error("BMC: the covariance matrix Q' is not positive definite");
    const double l = std::sqrt(d);
    a[size_t(j) * n + j] = l;
    for (int i = j + 1; i < n; ++i) {
      double v = a[size_t(i) * n + j];
      for (int k = 0; k < j; ++k) v -= a[size_t(i) * n + k] * a[size_t(j) * n + k];
      a[size_t(i) * n + j] = v / l;
    }
  }
  // L⁻¹ (lower triangular), then Q'⁻¹ = L⁻ᵗ L⁻¹.
  std::vector<double> inv_l(size_t(n) * n, 0.0);
  for (int j = 0; j < n; ++j) {
    inv_l[size_t(j) * n + j] = 1.0 / a[size_t(j) * n + j];
    for (int i = j + 1; i < n; ++i) {
      double v = 0.0;
      for (int k = j; k < i; ++k) v -= a[size_t(i) * n + k] * inv_l[size_t(k) * n + j];
      inv_l[size_t(i) * n + j] = v / a[size_t(i) * n + i];
    }
  }
  std::vector<double> inverse(size_t(n) * n, 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) {
      double v = 0.0;
      for (int k = i; k < n; ++k) v += inv_l[size_t(k) * n + i] * inv_l[size_t(k) * n + j];
      inverse[size_t(i) * n + j] = inverse[size_t(j) * n + i] = v;
    }
  return inverse;
}

Vec3 to_f(const Vec3d& v) {
  return Vec3(float(v.x), float(v.y), float(v.z));
}

}  // namespace

HemisphereMoments sg_hemisphere_moments(double cos_axis, double kappa) {
  // Circles of constant t = ω·a: ω·n = t c + √(1 − t²) s cos φ, c = a·n, s = √(1 − c²). A circle
  // lies wholly above the horizon for t > s (c > 0) or t < −s (c < 0), wholly below on the
  // other side, and crosses it for |t| < s, where the arc above is |φ| < φ0,
  // cos φ0 = −t c / (√(1 − t²) s). The arc's length is 2 φ0 and its ∫ ω·n dφ is
  // 2 (t c φ0 + √(1 − t²) s sin φ0).
  const double c = std::clamp(cos_axis, -1.0, 1.0), s = std::sqrt(std::max(0.0, 1.0 - c * c));
  HemisphereMoments m;
  if (c > 0.0) {
    m.area = 2.0 * kPiD * exp_integral(kappa, s, 1.0);
    m.cosine = 2.0 * kPiD * c * t_exp_integral(kappa, s, 1.0);
  } else if (c < 0.0) {
    m.area = 2.0 * kPiD * exp_integral(kappa, -1.0, -s);
    m.cosine = 2.0 * kPiD * c * t_exp_integral(kappa, -1.0, -s);
  }
  if (s <= 0.0) return m;
  // The crossing circles, t = s sin v: the arc ends move smoothly in v (φ0 = atan2(cos v,
  // −c sin v)), and the exponential peaks at v = π/2, where panels halve towards the end.
  const GaussLegendreRule& gl = panel_rule();
  const double peak_width = std::sqrt(2.0 / std::max(kappa * s, 1e-300));
  const int halvings = std::clamp(int(std::ceil(std::log2(0.5 * kPiD / peak_width))) + 2, 1, 40);
  const auto panel = [&](double lo, double hi) {
    const double half = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
    for (int i = 0; i < kPanelNodes; ++i) {
      const double v = mid + half * gl.x[size_t(i)], sv = std::sin(v), cv = std::cos(v);
      const double t = s * sv, weight = half * gl.w[size_t(i)] * std::exp(kappa * (t - 1.0)) * s * cv;
      const double phi0 = std::atan2(cv, -c * sv);
      const double rho = std::sqrt(std::max(0.0, 1.0 - t * t));  // √(1 − t²)
      const double sin_phi0 = cv / std::sqrt(cv * cv + c * c * sv * sv);
      m.area += weight * 2.0 * phi0;
      m.cosine += weight * 2.0 * (t * c * phi0 + rho * s * sin_phi0);
    }
  };
  panel(-0.5 * kPiD, 0.0);
  double lo = 0.0;
  for (int k = 1; k <= halvings; ++k) {
    const double hi = 0.5 * kPiD - 0.5 * kPiD * std::ldexp(1.0, -k);
    panel(lo, hi);
    lo = hi;
  }
  panel(lo, 0.5 * kPiD);
  return m;
}

std::vector<Vec3d> bmc_pattern(BmcLobe lobe, int count, double sharpness) {
  const double golden_angle = kPiD * (3.0 - std::sqrt(5.0));
  std::vector<Vec3d> pattern(static_cast<size_t>(count));
  for (int j = 0; j < count; ++j) {
    const double u = 1.0 - (j + 0.5) / count;  // uniform heights on the hemisphere
    // Eq. 25's warp in a form that neither overflows nor cancels for large m.
    const double z =
        lobe == BmcLobe::Cosine
            ? std::sqrt(u)
            : std::clamp(1.0 + std::log(u + (1.0 - u) * std::exp(-sharpness)) / sharpness, 0.0,
                         1.0);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = j * golden_angle;
    pattern[size_t(j)] = Vec3d(r * std::cos(phi), r * std::sin(phi), z);
  }
  return pattern;
}

std::shared_ptr<const BmcSampleSet> build_bmc_sample_set(BmcLobe lobe, int count, double sharpness,
                                                         double lengthscale, double noise) {
  auto set = std::make_shared<BmcSampleSet>();
  set->lobe = lobe;
  set->count = count;
  set->sharpness = sharpness;
  set->lengthscale = lengthscale;
  set->noise = noise;
  set->pattern = bmc_pattern(lobe, count, sharpness);
  const double inv_l2 = 1.0 / (lengthscale * lengthscale);
  std::vector<double> q(size_t(count) * count);
  for (int i = 0; i < count; ++i)
    for (int j = 0; j < count; ++j)
      q[size_t(i) * count + j] =
          std::exp((glm::dot(set->pattern[size_t(i)], set->pattern[size_t(j)]) - 1.0) * inv_l2) +
          (i == j ? noise * noise : 0.0);
  set->q_inverse = spd_inverse(std::move(q), count);
  // γ_j: the j-th column sum of Q'⁻¹; Γ: the sum of all its entries (Eq. 23).
  set->mean_weights.assign(size_t(count), 0.0);
  double total = 0.0;
  for (int i = 0; i < count; ++i)
    for (int j = 0; j < count; ++j)
      set->mean_weights[size_t(j)] += set->q_inverse[size_t(i) * count + j];
  for (double g : set->mean_weights) total += g;
  for (double& g : set->mean_weights) g /= total;
  if (lobe == BmcLobe::Cosine) {
    set->cosine_z.resize(size_t(count));
    for (int j = 0; j < count; ++j)
      set->cosine_z[size_t(j)] =
          sg_hemisphere_moments(set->pattern[size_t(j)].z, inv_l2).cosine / kPiD;
  }
  return set;
}

std::shared_ptr<const BmcSampleSet> bmc_sample_set(BmcLobe lobe, int count, double sharpness,
                                                   const BmcHyperparameters& hyper) {
  using Key = std::tuple<int, int, double, double, double>;
  static std::mutex mutex;
  static std::map<Key, std::shared_ptr<const BmcSampleSet>> cache;
  const double m = lobe == BmcLobe::Cosine ? 1.0 : sharpness;
  const Key key{int(lobe), count, m, hyper.noise, hyper.lengthscale_factor};
  std::lock_guard<std::mutex> lock(mutex);
  if (const auto it = cache.find(key); it != cache.end()) return it->second;
  // A textured exponent could ask for a set per shading point; keep the cache bounded.
  if (cache.size() >= 256) cache.clear();
  auto set =
      build_bmc_sample_set(lobe, count, m, hyper.lengthscale_factor / std::sqrt(m), hyper.noise);
  cache.emplace(key, set);
  return set;
}

BmcRule bmc_rule(const BmcSampleSet& set, const Vec3d& axis, double rotation) {
  const int n = set.count;
  const Vec3d lobe_axis = set.lobe == BmcLobe::Cosine ? Vec3d(0.0, 0.0, 1.0) : glm::normalize(axis);
  const FrameD frame(lobe_axis);
  const double angle = 2.0 * kPiD * rotation, ca = std::cos(angle), sa = std::sin(angle);
  std::vector<Vec3d> all(static_cast<size_t>(n));
  for (int j = 0; j < n; ++j) {
    const Vec3d& p = set.pattern[size_t(j)];
    all[size_t(j)] = frame.to_world(Vec3d(ca * p.x - sa * p.y, sa * p.x + ca * p.y, p.z));
  }

  // z' (Eqs. 21–22 for the Gaussian lobe: the product of the kernel about ω_j and the lobe
  // about a is c_m exp((ω_m·ω − 1)/l_m²), 1/l_m² = |ω_j/l² + a m| (the thesis's form), and μ).
  BmcRule rule;
  std::vector<double> z(static_cast<size_t>(n));
  if (set.lobe == BmcLobe::Cosine) {
    z = set.cosine_z;
    rule.lobe_integral = 1.0;
  } else {
    const double inv_l2 = 1.0 / (set.lengthscale * set.lengthscale), m = set.sharpness;
    for (int j = 0; j < n; ++j) {
      const Vec3d v = all[size_t(j)] * inv_l2 + lobe_axis * m;
      const double kappa = glm::length(v);
      const double c_m = std::exp(kappa - inv_l2 - m);
      z[size_t(j)] = c_m * sg_hemisphere_moments(v.z / kappa, kappa).area;
    }
    rule.lobe_integral = sg_hemisphere_moments(lobe_axis.z, m).area;
  }
  // Weights: Î = L̄ μ + z'ᵗ Q'⁻¹ (Y − L̄ H) = Σ_j (a_j + (γ_j/Γ)(μ − Σ_k a_k)) Y_j, a = Q'⁻¹ z'.
  std::vector<double> a(static_cast<size_t>(n), 0.0);
  double a_sum = 0.0;
  for (int i = 0; i < n; ++i) {
    double v = 0.0;
    const double* row = &set.q_inverse[size_t(i) * n];
    for (int k = 0; k < n; ++k) v += row[k] * z[size_t(k)];
    a[size_t(i)] = v;
    a_sum += v;
  }
  std::vector<double> weights(static_cast<size_t>(n));
  for (int j = 0; j < n; ++j)
    weights[size_t(j)] = a[size_t(j)] + set.mean_weights[size_t(j)] * (rule.lobe_integral - a_sum);

  rule.slots = all;
  rule.slot_weights = weights;
  // Below the horizon: the slot takes the value of the nearest direction above it.
  std::vector<int> above;
  for (int j = 0; j < n; ++j)
    if (all[size_t(j)].z > 0.0) above.push_back(j);
  if (above.empty()) return rule;
  std::vector<double> folded(static_cast<size_t>(n), 0.0);
  for (int j = 0; j < n; ++j) {
    int target = j;
    if (all[size_t(j)].z <= 0.0) {
      double best = -2.0;
      for (int k : above)
        if (const double d = glm::dot(all[size_t(j)], all[size_t(k)]); d > best) {
          best = d;
          target = k;
        }
    }
    folded[size_t(target)] += weights[size_t(j)];
  }
  for (int k : above) {
    rule.directions.push_back(all[size_t(k)]);
    rule.weights.push_back(folded[size_t(k)]);
  }
  return rule;
}

std::optional<Rgb> estimate_direct_bmc(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                       Rng& rng, int directions, const BmcHyperparameters& hyper) {
  const BsdfContext ctx{hit.uv, TransportMode::Radiance, hit.vertex_color};
  const std::optional<PhongLobes> lobes = hit.bsdf->phong_lobes(ctx);
  if (!lobes) return std::nullopt;
  const Vec3 wo_local = hit.shading.to_local(wo);
  // The Gaussian lobe needs a sharpness (Eq. 20's approximation is meant for m > 10; below 1
  // the fast rule's lengthscale exceeds the sphere): leave such lobes to the caller.
  const bool diffuse = !is_black(lobes->diffuse);
  const bool glossy = !is_black(lobes->specular);
  if (glossy && !(lobes->exponent >= 1.0f)) return std::nullopt;
  if (wo_local.z <= 0.0f) return Rgb(0.0f);  // one-sided, as the BSDFs it models

  // The radiance arriving along a local direction: what a ray finds (the environment or an
  // area emitter; zero if it hits anything else, or crosses to the other side of the surface).
  const auto arriving = [&](const Vec3d& local) {
    const Vec3 wi_local = to_f(local), wi = hit.shading.to_world(wi_local);
    if (!scene.sides_agree(hit.geometric_normal, wi, wi_local.z)) return Rgb(0.0f);
    SurfaceHit next;
    const bool found = scene.intersect(spawn_ray(hit.position, hit.geometric_normal, wi), next);
    return arriving_emission(scene, hit.position, wi, found ? &next : nullptr, false).radiance;
  };

  Rgb total(0.0f);
  const int per_lobe = std::max(1, diffuse && glossy ? directions / 2 : directions);
  if (diffuse) {
    const auto set = bmc_sample_set(BmcLobe::Cosine, per_lobe, 1.0, hyper);
    const BmcRule rule = bmc_rule(*set, Vec3d(0.0, 0.0, 1.0), rng.uniform());
    Rgb sum(0.0f);
    for (size_t j = 0; j < rule.directions.size(); ++j)
      sum += arriving(rule.directions[j]) * float(rule.weights[j]);
    total += lobes->diffuse * sum;
  }
  if (glossy) {
    // ρ cos θ = ks (n+2)/(2π) cos^n α cos θ is modelled by the Gaussian lobe
    // ks (n+2)/(2π) exp(n (cos α − 1)) (Eq. 20); what the lobe leaves out,
    // r = cos θ cos^n α / exp(n (cos α − 1)), multiplies the observed radiance ([T] §6.2: the
    // unknown function is then L_i ρ cos / p).
    const double m = lobes->exponent;
    const Vec3d mirror(-wo_local.x, -wo_local.y, wo_local.z);
    const auto set = bmc_sample_set(BmcLobe::Gaussian, per_lobe, m, hyper);
    const Vec3d axis = glm::normalize(mirror);
    const BmcRule rule = bmc_rule(*set, axis, rng.uniform());
    Rgb sum(0.0f);
    for (size_t j = 0; j < rule.directions.size(); ++j) {
      const Vec3d& w = rule.directions[j];
      const double cos_alpha = glm::dot(w, axis);
      if (cos_alpha <= 0.0) continue;
      const double ratio = w.z * std::exp(m * (std::log(cos_alpha) - cos_alpha + 1.0));
      sum += arriving(w) * float(rule.weights[j] * ratio);
    }
    total += lobes->specular * float((m + 2.0) / (2.0 * kPiD)) * sum;
  }

  // Delta lights: no direction finds them; each is sampled once (its one point or direction).
  const LightSet& lights = scene.lights();
  for (size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights.light(i);
    if (!light.is_delta()) continue;
    const auto ls = light.sample_direct(hit.position, rng.uniform2());
    if (!ls || ls->pdf <= 0.0f || is_black(ls->radiance)) continue;
    const Vec3 wi_local = hit.shading.to_local(ls->wi);
    if (!scene.sides_agree(hit.geometric_normal, ls->wi, wi_local.z)) continue;
    const Rgb f = hit.bsdf->eval(ctx, wo_local, wi_local);
    if (is_black(f)) continue;
    const bool unoccluded =
        light.at_infinity()
            ? !scene.occluded(spawn_ray(hit.position, hit.geometric_normal, ls->wi))
            : scene.visible(hit.position, hit.geometric_normal, ls->position, ls->normal);
    if (unoccluded) total += f * std::abs(wi_local.z) * ls->radiance / ls->pdf;
  }
  return total;
}

}  // namespace emlt
