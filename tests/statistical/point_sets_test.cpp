// The randomised Sobol, Larcher-Pillichshammer and blue-noise point sets
// (core/sobol_points.h, core/larcher_pillichshammer_points.h, core/blue_noise_points.h) as
// the direct-lighting estimator uses them: every point marginally uniform (chi-square over
// randomisations), the estimate unbiased where the unrandomised set is not, below
// independent sampling's error on a smooth integrand, and the direct estimate under a
// constant sky converging to albedo times radiance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "emlt/core/blue_noise_points.h"
#include "emlt/core/larcher_pillichshammer_points.h"
#include "emlt/core/sobol_points.h"
#include "emlt/core/spherical_fibonacci.h"
#include "emlt/sampling/direct_lighting.h"
#include "emlt/scene/materials.h"
#include "support/test_scenes.h"

using namespace emlt;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// A set of n points randomised from rng; `randomised` false gives the set before its
// randomisation (zero scramble, zero shift).
using PointSet = std::function<std::vector<Vec2>(uint32_t n, Rng& rng, bool randomised)>;

struct NamedSet {
  const char* name;
  PointSet points;
};

std::vector<NamedSet> sets() {
  return {
      {"sobol",
       [](uint32_t n, Rng& rng, bool r) {
         return sobol_square_points(n, r ? DigitScramble::draw(rng) : DigitScramble{});
       }},
      {"larcher-pillichshammer",
       [](uint32_t n, Rng& rng, bool r) {
         return larcher_pillichshammer_square_points(
             n, r ? DigitScramble::draw(rng) : DigitScramble{});
       }},
      {"blue-noise",
       [](uint32_t n, Rng& rng, bool r) {
         return blue_noise_square_points(n, r ? rng.uniform2() : Vec2(0.0f));
       }},
  };
}

// Chi-square of point `index`'s position over `trials` randomisations, on a 32 x 32 grid.
double chi_square_of_point(const PointSet& set, uint32_t n, uint32_t index, int trials) {
  constexpr int kBins = 32;
  std::vector<int> count(kBins * kBins, 0);
  Rng rng(17, n * 1000 + index);
  for (int t = 0; t < trials; ++t) {
    const Vec2 p = set(n, rng, true)[index];
    ++count[size_t(int(p.y * kBins) * kBins + int(p.x * kBins))];
  }
  const double expected = double(trials) / (kBins * kBins);
  double chi2 = 0.0;
  for (int c : count) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

// The full-sphere integral of a smooth lobe exp(k (w.d - 1)), 2 pi (1 - exp(-2k)) / k,
// estimated from a unit-square set through Lambert's equal-area map.
constexpr double kLobe = 6.0;
const Vec3 kLobeAxis = glm::normalize(Vec3(0.4f, -0.3f, 0.7f));
double lobe_exact() {
  return 2.0 * kPiD * (1.0 - std::exp(-2.0 * kLobe)) / kLobe;
}
double lobe_estimate(const std::vector<Vec2>& points) {
  double sum = 0.0;
  for (const Vec2& p : points)
    sum += std::exp(kLobe * (double(glm::dot(lambert_sphere_direction(p), kLobeAxis)) - 1.0));
  return 4.0 * kPiD * sum / double(points.size());
}

struct Moments {
  double mean, se, rmse;
};
Moments lobe_moments(const PointSet& set, uint32_t n, int trials, bool randomised) {
  Rng rng(23, n);
  double sum = 0.0, sum2 = 0.0;
  for (int t = 0; t < trials; ++t) {
    const double e = lobe_estimate(set(n, rng, randomised)) - lobe_exact();
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / trials;
  return {mean, std::sqrt(std::max(sum2 / trials - mean * mean, 0.0) / trials),
          std::sqrt(sum2 / trials)};
}

}  // namespace

// 1023 degrees of freedom: mean 1023, standard deviation 45; the bound is 6 of them above.
// The first, a middle and the last point, at a power of two and at 384.
TEST(PointSetRandomisation, EveryPointIsMarginallyUniform) {
  for (const NamedSet& s : sets())
    for (uint32_t n : {16u, 384u})
      for (uint32_t index : {0u, n / 2 + 1, n - 1})
        EXPECT_LT(chi_square_of_point(s.points, n, index, 16384), 1023.0 + 6.0 * 45.2)
            << s.name << " n=" << n << " point " << index;
}

// Unbiased: the mean error over randomisations is within 4 standard errors of zero. The same
// sets unrandomised carry a deterministic error (measured at n = 16: Sobol 34, L-P 13, blue
// noise 38 standard errors away), which this test would see; a randomisation that did not
// move the points (standard error 0) fails it at once.
TEST(PointSetRandomisation, EstimateIsUnbiasedWhereTheBareSetIsNot) {
  for (const NamedSet& s : sets())
    for (uint32_t n : {16u, 384u}) {
      const Moments m = lobe_moments(s.points, n, 4000, true);
      EXPECT_LT(std::abs(m.mean), 4.0 * m.se + 1e-7) << s.name << " n=" << n;
      if (n == 16) {
        const Moments bare = lobe_moments(s.points, n, 1, false);
        std::printf("%s: the bare set's error is %.1f standard errors\n", s.name, bare.mean / m.se);
        EXPECT_GT(std::abs(bare.mean), 8.0 * m.se) << s.name << " " << bare.mean / m.se;
      }
    }
}

// At n = 256 on the smooth lobe. Measured RMSE relative to independent points: Sobol 0.075,
// Larcher-Pillichshammer 0.036, blue noise 0.27 (the bounds are about twice these).
TEST(PointSetRandomisation, SmoothIntegrandErrorAtN256IsBelowIndependentSampling) {
  const PointSet independent = [](uint32_t n, Rng& rng, bool) {
    std::vector<Vec2> p(n);
    for (Vec2& q : p) q = rng.uniform2();
    return p;
  };
  const double mc = lobe_moments(independent, 256, 400, true).rmse;
  const double bound[] = {0.15, 0.08, 0.5};
  int i = 0;
  for (const NamedSet& s : sets()) {
    const double rmse = lobe_moments(s.points, 256, 400, true).rmse;
    std::printf("%s: RMSE / independent %.4f\n", s.name, rmse / mc);
    EXPECT_LT(rmse, bound[i++] * mc) << s.name << " " << rmse / mc;
  }
}

// The direct-lighting estimator with each set: a diffuse floor of albedo 0.5 under a
// constant sky of radiance 2 reflects 1 (light and BSDF samples with MIS), at n = 16 and at a
// non-power of two; the mean over estimates is within 4 standard errors, and the standard
// deviation is well below independent sampling's (so the estimator does draw from the set;
// measured ratios in the test's output).
TEST(PointSetDirectLighting, ConstantSkyGivesAlbedoTimesRadiance) {
  SceneDescription d;
  d.source = "point-set-floor";
  const int m = test::add_material(d, make_lambertian(Rgb(0.5f)));
  test::add_quad(d, Vec3(-100, 0, -100), Vec3(-100, 0, 100), Vec3(100, 0, 100), Vec3(100, 0, -100),
                 m);
  d.environment.kind = EnvironmentDesc::Kind::Constant;
  d.environment.radiance = Rgb(2.0f);
  d.camera = test::camera_at(Vec3(0, 2, 0), Vec3(0.1f, 0, 0.1f), 16, Vec3(0, 0, 1));
  const auto scene = Scene::build(std::move(d));
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.2f, 2, 0.3f), Vec3(0, -1, 0)}, hit));
  const auto moments = [&](DirectPointSet set, int n, double* sd) {
    DirectLightingOptions options;
    options.samples = n;
    options.point_set = set;
    const int trials = 2000;
    double sum = 0.0, sum2 = 0.0;
    for (int t = 0; t < trials; ++t) {
      Rng rng(29, uint64_t(t));
      const double v = estimate_direct_lighting(*scene, hit, Vec3(0, 1, 0), rng, options).y;
      sum += v;
      sum2 += v * v;
    }
    const double mean = sum / trials;
    *sd = std::sqrt(std::max(sum2 / trials - mean * mean, 0.0));
    return mean;
  };
  for (int n : {16, 48}) {
    double sd_independent;
    moments(DirectPointSet::Independent, n, &sd_independent);
    for (DirectPointSet set : {DirectPointSet::Sobol, DirectPointSet::LarcherPillichshammer,
                               DirectPointSet::BlueNoise}) {
      double sd;
      const double mean = moments(set, n, &sd);
      std::printf("%s n=%d: mean %.5f, sd / independent's %.3f\n", direct_point_set_name(set), n,
                  mean, sd / sd_independent);
      EXPECT_NEAR(mean, 1.0, 4.0 * sd / std::sqrt(2000.0) + 1e-6)
          << direct_point_set_name(set) << " n=" << n;
      EXPECT_GT(sd, 0.0) << direct_point_set_name(set);
      EXPECT_LT(sd, 0.7 * sd_independent) << direct_point_set_name(set) << " n=" << n;
    }
  }
}
