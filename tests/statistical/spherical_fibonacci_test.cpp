#include <gtest/gtest.h>

#include "emlt/core/spherical_fibonacci.h"
#include "emlt/core/warp.h"

using namespace emlt;

TEST(SphericalFibonacci, EnergyDecaysAsNToTheMinusThreeQuarters) {
  // E_N(SF) * N^(3/4) lies in [0.89, 0.92] for N in [64, 4096];
  // random points give E[E_N^2] = 4/(3N), i.e. far larger.
  for (uint32_t n : {64u, 256u, 1024u}) {
    std::vector<Vec3> points;
    for (const Vec2& p : fibonacci_square_points(n, {0.0f, 0.0f})) points.push_back(lambert_sphere_direction(p));
    const double scaled = spherical_energy(points) * std::pow(double(n), 0.75);
    EXPECT_GT(scaled, 0.85) << n;
    EXPECT_LT(scaled, 0.95) << n;
    const double random_energy = std::sqrt(4.0 / (3.0 * n));
    EXPECT_LT(spherical_energy(points), 0.5 * random_energy) << n;
  }
}

TEST(SphericalFibonacci, RotationDoesNotChangeEnergy) {
  std::vector<Vec3> a, b;
  for (const Vec2& p : fibonacci_square_points(256, {0.0f, 0.0f})) a.push_back(lambert_sphere_direction(p));
  for (const Vec2& p : fibonacci_square_points(256, {0.37f, 0.0f})) b.push_back(lambert_sphere_direction(p));
  EXPECT_NEAR(spherical_energy(a), spherical_energy(b), 1e-5);
}

namespace {
// Mean over randomisations of the N-point estimate of the hemispherical integral of
// cos^2(theta) (exact value 2 pi / 3).
void estimate_cos2(uint32_t n, bool shift, int trials, double* mean, double* se) {
  Rng rng(42, n);
  double sum = 0.0, sum2 = 0.0;
  for (int t = 0; t < trials; ++t) {
    FibonacciRandomisation r = FibonacciRandomisation::draw(rng);
    if (!shift) r.shift = 0.0f;
    double estimate = 0.0;
    for (uint32_t j = 0; j < n; ++j) {
      const Vec3 w = lambert_hemisphere_direction(fibonacci_square_point(j, n, r));
      estimate += double(w.z) * w.z / uniform_hemisphere_pdf(w);
    }
    estimate /= n;
    sum += estimate;
    sum2 += estimate * estimate;
  }
  *mean = sum / trials;
  *se = std::sqrt(std::max(sum2 / trials - *mean * *mean, 0.0) / trials);
}
}  // namespace

TEST(SphericalFibonacci, ShiftedSetIsUnbiased) {
  const double exact = 2.0 * M_PI / 3.0;
  for (uint32_t n : {4u, 16u}) {
    double mean, se;
    estimate_cos2(n, true, 200000, &mean, &se);
    EXPECT_NEAR(mean, exact, 4.0 * se + 1e-6) << n;
  }
}

TEST(SphericalFibonacci, RotationOnlyCarriesTheMidpointBias) {
  // Without the Cranley-Patterson shift the estimate is deterministic in z: its bias is
  // exactly -pi/(6 N^2), which the unbiased variant removes.
  const double exact = 2.0 * M_PI / 3.0;
  const uint32_t n = 4;
  double mean, se;
  estimate_cos2(n, false, 1000, &mean, &se);
  EXPECT_NEAR(mean - exact, -M_PI / (6.0 * n * n), 1e-5);
  EXPECT_GT(std::abs(mean - exact), 100.0 * (se + 1e-6));
}

TEST(SphericalFibonacci, BeatsIndependentSamplingOnALightCap) {
  // Irradiance from a cap light (centre 40 deg from the normal, half-angle 20 deg) with
  // cosine-weighted directions: exact value (d.n) pi sin^2(alpha) = 0.281518674.
  const double exact = 0.281518674;
  const float beta = glm::radians(40.0f), alpha = glm::radians(20.0f);
  const Vec3 axis(std::sin(beta), 0.0f, std::cos(beta));
  const uint32_t n = 256;
  const auto rmse = [&](bool fibonacci) {
    Rng rng(7, fibonacci ? 1 : 0);
    double sq = 0.0;
    const int trials = 400;
    for (int t = 0; t < trials; ++t) {
      const FibonacciRandomisation r = FibonacciRandomisation::draw(rng);
      double e = 0.0;
      for (uint32_t j = 0; j < n; ++j) {
        const Vec2 p = fibonacci ? fibonacci_square_point(j, n, r) : rng.uniform2();
        // Cosine-weighted via the Lambert lift: z = sqrt(1 - y).
        const float z = std::sqrt(1.0f - p.y), rr = safe_sqrt(1.0f - z * z);
        const Vec3 w(rr * std::cos(kTwoPi * p.x), rr * std::sin(kTwoPi * p.x), z);
        if (glm::dot(w, axis) >= std::cos(alpha)) e += kPi;  // L cos / (cos/pi)
      }
      e /= n;
      sq += (e - exact) * (e - exact);
    }
    return std::sqrt(sq / trials);
  };
  const double sf = rmse(true), iid = rmse(false);
  EXPECT_LT(sf * 3.0, iid) << "SF " << sf << " iid " << iid;
}
