#include "src/scene/materials/rough_transmittance.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "emlt/core/gauss_legendre.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/microfacet.h"

namespace emlt {
namespace {

constexpr int kMuNodes = 128;  // table nodes, uniform in sqrt(mu)
// Quadrature sizes: each halving changes the results by under 3e-5 (checked against rules
// four times finer); the cost is about 2e5 integrand evaluations per roughness.
constexpr int kNormalNodes = 24;     // per axis, for one direction's integral
constexpr int kDiffuseMuNodes = 32;  // per piece of [0, 1] (two when eta < 1)
constexpr int kDiffuseNormalNodes = 32;
constexpr int kAlphaNodes = 16;  // textured roughness, quadratic in alpha
constexpr double kMinMu = 1e-5;  // T at mu = 0 is taken as its limit
constexpr double kPiDouble = 3.14159265358979323846;

struct GaussLegendre {
  std::vector<double> x, w;  // on [0, 1]
};

// The n-point Gauss-Legendre rule moved onto [0, 1] (halving the weights is exact).
GaussLegendre gauss_legendre_unit(int n) {
  const GaussLegendreRule rule = gauss_legendre(n);
  GaussLegendre unit{std::vector<double>(size_t(n)), std::vector<double>(size_t(n))};
  for (size_t i = 0; i < size_t(n); ++i) {
    unit.x[i] = 0.5 * (1.0 + rule.x[i]);
    unit.w[i] = 0.5 * rule.w[i];
  }
  return unit;
}

// cos(theta_m) of the microfacet normal whose D(m) m.z-measure of steeper normals is s^2:
// with u = 1 - s^2 uniform, m is distributed as D(m) m.z. The substitution keeps the
// integrand finite where GGX's tail reaches grazing normals (there 1 / cos_m ~ 1 / s).
double cos_theta_of(const MicrofacetDistribution& dist, double s) {
  const double alpha = dist.alpha_u();
  switch (dist.type()) {
    case MicrofacetType::Ggx:  // tan^2 = alpha^2 u / (1 - u)
      return s / std::sqrt(s * s + alpha * alpha * (1.0 - s * s));
    case MicrofacetType::Beckmann:  // tan^2 = -alpha^2 ln(1 - u)
      return 1.0 / std::sqrt(1.0 - 2.0 * alpha * alpha * std::log(s));
    case MicrofacetType::Phong: {  // D ~ cos^e: 1 - u = cos^(e + 2)
      const double exponent = std::max(2.0 / (alpha * alpha) - 2.0, 0.0);
      return std::pow(s, 2.0 / (exponent + 2.0));
    }
  }
  return 1.0;
}

}  // namespace

double RoughTransmittance::integrate(MicrofacetType type, float alpha, float eta, double mu,
                                     int nodes) {
  const MicrofacetDistribution dist(type, alpha);
  const GaussLegendre rule = gauss_legendre_unit(nodes);
  mu = std::clamp(mu, kMinMu, 1.0);
  const double sin_i = std::sqrt(std::max(0.0, 1.0 - mu * mu));
  const Vec3 w(static_cast<float>(sin_i), 0.0f, static_cast<float>(mu));
  double total = 0.0;
  for (int a = 0; a < nodes; ++a) {
    const double s = rule.x[a];
    const double cos_m = cos_theta_of(dist, s);
    const double sin_m = std::sqrt(std::max(0.0, 1.0 - cos_m * cos_m));
    // Azimuths (from w's, both signs alike) at which w sees the front of m:
    // sin_m sin_i cos(phi) + cos_m mu > 0.
    const double threshold = sin_m * sin_i > 0.0 ? -cos_m * mu / (sin_m * sin_i) : -2.0;
    const double phi_max = std::acos(std::clamp(threshold, -1.0, 1.0));
    if (phi_max <= 0.0) continue;
    // du = 2 s ds; the azimuth's share of the full circle is phi_max / pi.
    const double row_weight = rule.w[a] * 2.0 * s * (phi_max / kPiDouble) / (mu * cos_m);
    double row = 0.0;
    for (int b = 0; b < nodes; ++b) {
      const double phi = phi_max * rule.x[b];
      const Vec3 m(static_cast<float>(sin_m * std::cos(phi)),
                   static_cast<float>(sin_m * std::sin(phi)), static_cast<float>(cos_m));
      const float cos_wm = glm::dot(w, m);
      if (cos_wm <= 0.0f) continue;
      float cos_t = 0.0f;
      const float fresnel = fresnel_dielectric(cos_wm, eta, &cos_t);
      if (fresnel >= 1.0f) continue;  // total internal reflection at this facet
      // Refraction about m: -w / eta + (cos_wm / eta + cos_t) m, with cos_t < 0.
      const Vec3 refracted = -w / eta + (cos_wm / eta + cos_t) * m;
      const float shadowing = dist.G1(w, m) * dist.G1(refracted, m);
      row += rule.w[b] * (1.0 - fresnel) * shadowing * cos_wm;
    }
    total += row_weight * row;
  }
  return total;
}

double RoughTransmittance::integrate_diffuse(MicrofacetType type, float alpha, float eta,
                                             int mu_nodes, int nodes) {
  // From the denser side the transmittance drops to zero over a narrow range of mu at the
  // critical angle (exactly there when smooth): split the rule at it.
  std::vector<std::pair<double, double>> pieces{{0.0, 1.0}};
  if (eta < 1.0f) {
    const double critical = std::sqrt(1.0 - double(eta) * eta);
    pieces = {{0.0, critical}, {critical, 1.0}};
  }
  const GaussLegendre rule = gauss_legendre_unit(mu_nodes);
  double total = 0.0;
  for (const auto& [lo, hi] : pieces) {
    for (int i = 0; i < mu_nodes; ++i) {
      const double mu = lo + (hi - lo) * rule.x[i];
      total += (hi - lo) * rule.w[i] * 2.0 * mu * integrate(type, alpha, eta, mu, nodes);
    }
  }
  return total;
}

RoughTransmittance::RoughTransmittance(MicrofacetType type, float eta, float alpha,
                                       float alpha_max) {
  if (alpha_max > 0.0f) {
    for (int j = 0; j < kAlphaNodes; ++j) {
      const float t = float(j) / (kAlphaNodes - 1);
      alphas_.push_back(alpha_max * t * t);
    }
  } else {
    alphas_.push_back(alpha);
  }
  // Every entry is its own integral: computed in parallel (loading is otherwise serial, and a
  // material's two tables took 80 M instructions of loading the public Veach door), each
  // the same number whichever thread computes it.
  const size_t rows = alphas_.size(), per_row = size_t(kMuNodes) + 1;
  table_.assign(rows * size_t(kMuNodes), 0.0f);
  diffuse_.assign(rows, 0.0f);
  tbb::parallel_for(size_t(0), rows * per_row, [&](size_t k) {
    const size_t row = k / per_row, i = k % per_row;
    const float a = alphas_[row];
    if (i == size_t(kMuNodes)) {
      diffuse_[row] = static_cast<float>(
          integrate_diffuse(type, a, eta, kDiffuseMuNodes, kDiffuseNormalNodes));
      return;
    }
    const double t = double(i) / (kMuNodes - 1);
    table_[row * size_t(kMuNodes) + i] =
        static_cast<float>(integrate(type, a, eta, t * t, kNormalNodes));
  });
}

std::pair<int, float> RoughTransmittance::alpha_position(float alpha) const {
  const int n = static_cast<int>(alphas_.size());
  if (n == 1 || !(alpha > alphas_.front())) return {0, 0.0f};
  if (alpha >= alphas_.back()) return {n - 2, 1.0f};
  const int j =
      static_cast<int>(std::upper_bound(alphas_.begin(), alphas_.end(), alpha) - alphas_.begin()) -
      1;
  return {j, (alpha - alphas_[j]) / (alphas_[j + 1] - alphas_[j])};
}

float RoughTransmittance::operator()(float mu, float alpha) const {
  const float x = std::sqrt(std::clamp(mu, 0.0f, 1.0f)) * (kMuNodes - 1);
  const int i = std::min(static_cast<int>(x), kMuNodes - 2);
  const float f = x - i;
  auto row = [&](int j) {
    const float* r = &table_[size_t(j) * kMuNodes];
    return r[i] + f * (r[i + 1] - r[i]);
  };
  const auto [j, g] = alpha_position(alpha);
  if (alphas_.size() == 1) return row(0);
  return row(j) + g * (row(j + 1) - row(j));
}

float RoughTransmittance::diffuse(float alpha) const {
  const auto [j, g] = alpha_position(alpha);
  if (diffuse_.size() == 1) return diffuse_[0];
  return diffuse_[j] + g * (diffuse_[j + 1] - diffuse_[j]);
}

}  // namespace emlt
