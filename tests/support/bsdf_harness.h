#pragma once
// Header-only BSDF test harness shared by the statistical suites: a chi-square test of
// sample() against pdf() over the whole sphere (whose extra cell catches lost or surplus
// mass), albedo estimates, and direction helpers. Same method as tests/statistical/
// bsdf_test.cpp, parametrised by the BsdfContext so textured and importance-mode
// materials can be tested too.
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/scene/bsdf.h"
#include "support/test_support.h"

namespace emlt::test {

inline Vec3 spherical_direction(double cos_theta, double phi) {
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return {float(sin_theta * std::cos(phi)), float(sin_theta * std::sin(phi)), float(cos_theta)};
}

// An incident direction at the given (signed) cosine; the azimuth avoids cell boundaries.
inline Vec3 incident(float cos_theta) { return spherical_direction(cos_theta, 0.7); }

using DirectionalDensity = std::function<double(const Vec3& wi)>;

struct ChiSquareSetup {
  int cos_bins = 20, phi_bins = 40, samples = 200000;
};

struct ChiSquareOutcome {
  ChiSquareResult chi2;
  double density_integral = 0.0;  // integral of the density over the sphere
  double sampled_fraction = 0.0;  // fraction of sample() calls giving a non-delta wi
};

namespace detail {

inline double integrate_patch(const DirectionalDensity& density, double theta0, double theta1,
                              double phi0, double phi1, double coarse, int depth) {
  const auto f = [&](double theta, double phi) {
    return density(spherical_direction(std::cos(theta), phi)) * std::sin(theta);
  };
  const double theta_mid = 0.5 * (theta0 + theta1), phi_mid = 0.5 * (phi0 + phi1);
  const double q[4] = {integrate_2d(f, theta0, theta_mid, phi0, phi_mid, 4),
                       integrate_2d(f, theta_mid, theta1, phi0, phi_mid, 4),
                       integrate_2d(f, theta0, theta_mid, phi_mid, phi1, 4),
                       integrate_2d(f, theta_mid, theta1, phi_mid, phi1, 4)};
  const double fine = q[0] + q[1] + q[2] + q[3];
  if (depth == 0 || std::abs(fine - coarse) < 1e-8 + 1e-5 * std::abs(fine)) return fine;
  return integrate_patch(density, theta0, theta_mid, phi0, phi_mid, q[0], depth - 1) +
         integrate_patch(density, theta_mid, theta1, phi0, phi_mid, q[1], depth - 1) +
         integrate_patch(density, theta0, theta_mid, phi_mid, phi1, q[2], depth - 1) +
         integrate_patch(density, theta_mid, theta1, phi_mid, phi1, q[3], depth - 1);
}

}  // namespace detail

// Histograms non-delta samples of wi against `density` integrated per (cos theta, phi)
// cell; one extra cell holds failed and delta samples against the mass the density
// leaves out.
inline ChiSquareOutcome run_chi_square(const Bsdf& bsdf, const BsdfContext& ctx, const Vec3& wo,
                                       const DirectionalDensity& density, uint64_t seed,
                                       const ChiSquareSetup& setup = {}) {
  const int cells = setup.cos_bins * setup.phi_bins;
  const auto cell_of = [&](const Vec3& w) {
    const double c = std::clamp(double(w.z), -1.0, 1.0);
    double phi = std::atan2(double(w.y), double(w.x));
    if (phi < 0.0) phi += 2.0 * M_PI;
    const int i = std::min(setup.cos_bins - 1, int((c + 1.0) * 0.5 * setup.cos_bins));
    const int j = std::min(setup.phi_bins - 1, int(phi / (2.0 * M_PI) * setup.phi_bins));
    return i * setup.phi_bins + j;
  };
  Rng rng(seed, 0);
  std::vector<double> observed(cells + 1, 0.0), expected(cells + 1, 0.0);
  int histogrammed = 0;
  for (int n = 0; n < setup.samples; ++n) {
    const float u_lobe = rng.uniform();
    const auto s = bsdf.sample(ctx, wo, u_lobe, rng.uniform2());
    if (!s || s->is_delta()) continue;
    observed[cell_of(s->wi)] += 1.0;
    ++histogrammed;
  }
  observed[cells] = setup.samples - histogrammed;
  ChiSquareOutcome outcome;
  for (int i = 0; i < setup.cos_bins; ++i) {
    const double cos_lo = -1.0 + 2.0 * i / setup.cos_bins;
    const double cos_hi = -1.0 + 2.0 * (i + 1) / setup.cos_bins;
    const double theta0 = std::acos(cos_hi), theta1 = std::acos(cos_lo);
    for (int j = 0; j < setup.phi_bins; ++j) {
      const double phi0 = 2.0 * M_PI * j / setup.phi_bins;
      const double phi1 = 2.0 * M_PI * (j + 1) / setup.phi_bins;
      const auto f = [&](double theta, double phi) {
        return density(spherical_direction(std::cos(theta), phi)) * std::sin(theta);
      };
      const double coarse = integrate_2d(f, theta0, theta1, phi0, phi1, 4);
      const double mass = detail::integrate_patch(density, theta0, theta1, phi0, phi1, coarse, 6);
      expected[i * setup.phi_bins + j] = mass * setup.samples;
      outcome.density_integral += mass;
    }
  }
  expected[cells] = std::max(0.0, 1.0 - outcome.density_integral) * setup.samples;
  outcome.chi2 = chi_square_test(observed, expected);
  outcome.sampled_fraction = double(histogrammed) / setup.samples;
  return outcome;
}

inline DirectionalDensity density_of(const Bsdf& bsdf, const BsdfContext& ctx, const Vec3& wo) {
  return [&bsdf, ctx, wo](const Vec3& wi) { return double(bsdf.pdf(ctx, wo, wi)); };
}

struct Albedo {
  Rgb mean{0.0f};
  Rgb standard_error{0.0f};
};

// E[weight] over sample(); failed samples contribute zero.
inline Albedo estimate_albedo(const Bsdf& bsdf, const BsdfContext& ctx, const Vec3& wo,
                              int samples, uint64_t seed) {
  Rng rng(seed, 0);
  DVec3 sum(0.0), sum2(0.0);
  for (int n = 0; n < samples; ++n) {
    const auto s = bsdf.sample(ctx, wo, rng.uniform(), rng.uniform2());
    if (!s) continue;
    const DVec3 w(s->weight);
    sum += w;
    sum2 += w * w;
  }
  const DVec3 mean = sum / double(samples);
  const DVec3 variance = glm::max(sum2 / double(samples) - mean * mean, DVec3(0.0));
  return {Rgb(mean), Rgb(glm::sqrt(variance / double(samples)))};
}

}  // namespace emlt::test
