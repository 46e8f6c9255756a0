// Bayesian Monte Carlo with spherical Gaussians (sampling/bmc_direct_estimator.h): the
// hemispherical spherical-Gaussian integrals against closed forms and brute force, the
// quadrature exact on the functions its Gaussian process is built from, constant radiance
// exact under the horizon, a spherical-Gaussian environment on a glossy lobe converging to its
// analytic integral faster than importance sampling, and the furnace through the renderer.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "emlt/core/gauss_legendre.h"
#include "emlt/integrators/direct_integrator.h"
#include "emlt/sampling/bmc_direct_estimator.h"
#include "emlt/sampling/direct_lighting.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "support/mlt_test_helpers.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

constexpr double kPiD = 3.14159265358979323846;

Vec3d tilted(double degrees) {
  const double t = degrees * kPiD / 180.0;
  return Vec3d(std::sin(t), 0.0, std::cos(t));
}

// ∫ over the hemisphere z > 0 of g, by Gauss–Legendre in z (composite, 8 panels of 32 graded
// towards z = 1) and the trapezoid rule in φ (exact for trigonometric polynomials): the
// integrands below are smooth on [0, 1] × the circle, so this converges to machine precision.
template <class F>
double hemisphere_quadrature(F&& g, int phi_steps = 720) {
  static std::vector<double> x, w;
  if (x.empty()) {
    const int n = 32;
    const GaussLegendreRule rule = gauss_legendre(n);
    const std::vector<double>& gx = rule.x;
    const std::vector<double>& gw = rule.w;
    const double edges[] = {0.0, 0.5, 0.75, 0.875, 0.9375, 0.96875, 0.984375, 0.9921875, 1.0};
    for (int p = 0; p < 8; ++p)
      for (int i = 0; i < n; ++i) {
        const double half = 0.5 * (edges[p + 1] - edges[p]);
        x.push_back(edges[p] + half * (1.0 + gx[size_t(i)]));
        w.push_back(half * gw[size_t(i)]);
      }
  }
  double sum = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double z = x[i], r = std::sqrt(std::max(0.0, 1.0 - z * z));
    double ring = 0.0;
    for (int k = 0; k < phi_steps; ++k) {
      const double phi = 2.0 * kPiD * (k + 0.5) / phi_steps;
      ring += g(Vec3d(r * std::cos(phi), r * std::sin(phi), z));
    }
    sum += w[i] * ring * (2.0 * kPiD / phi_steps);
  }
  return sum;
}

double sg(const Vec3d& axis, double kappa, const Vec3d& w) {
  return std::exp(kappa * (glm::dot(axis, w) - 1.0));
}

}  // namespace

TEST(BmcSphericalGaussians, HemisphereIntegralsMatchClosedFormsAndBruteForce) {
  for (double kappa : {0.64, 11.1, 200.0}) {
    const double l2 = 1.0 / kappa;
    const HemisphereMoments up = sg_hemisphere_moments(1.0, kappa),
                            side = sg_hemisphere_moments(0.0, kappa),
                            down = sg_hemisphere_moments(-1.0, kappa);
    EXPECT_NEAR(up.area, 2.0 * kPiD * l2 * (1.0 - std::exp(-kappa)), 1e-12 * up.area);
    EXPECT_NEAR(side.area, kPiD * l2 * (1.0 - std::exp(-2.0 * kappa)), 1e-12 * side.area);
    EXPECT_NEAR(down.area, 2.0 * kPiD * l2 * (std::exp(-kappa) - std::exp(-2.0 * kappa)),
                1e-10 * down.area + 1e-300);
  }
  // The seed digest's table values for l = 0.3, to the digits it prints (six, then three);
  // its 120° value, 0.027310, is 4e-5 above ours, which brute force below confirms to 1e-7.
  const double degrees[] = {0, 30, 60, 90, 120, 150, 180};
  const double table[] = {0.565478, 0.565070, 0.538177, 0.282743, 0.027310, 4.17e-4, 8.45e-6};
  for (int i = 0; i < 7; ++i)
    EXPECT_NEAR(sg_hemisphere_moments(std::cos(degrees[i] * kPiD / 180.0), 1.0 / 0.09).area,
                table[i], (i < 5 ? 5e-5 : 2e-3) * table[i])
        << degrees[i];
  // Both moments against brute force, at axes all around the horizon.
  for (double kappa : {2.0, 30.0, 300.0})
    for (double angle : {10.0, 50.0, 85.0, 95.0, 130.0}) {
      const Vec3d a = tilted(angle);
      const HemisphereMoments m = sg_hemisphere_moments(a.z, kappa);
      const int steps = kappa > 100.0 ? 2880 : 720;
      const double area =
          hemisphere_quadrature([&](const Vec3d& w) { return sg(a, kappa, w); }, steps);
      const double cosine =
          hemisphere_quadrature([&](const Vec3d& w) { return sg(a, kappa, w) * w.z; }, steps);
      EXPECT_NEAR(m.area, area, 1e-7 * area + 1e-14) << kappa << " " << angle;
      EXPECT_NEAR(m.cosine, cosine, 1e-7 * cosine + 1e-14) << kappa << " " << angle;
    }
}

TEST(BmcQuadrature, ExactOnTheFunctionsOfItsGaussianProcess) {
  // With the noise ratio near zero the posterior mean interpolates: the rule integrates exactly
  // any f = c + Σ_j a_j k'(·, ω_j) with Σ_j a_j = 0 (the constant is the prior mean's basis
  // function, Eq. 23), over the hemisphere, against the lobe, wherever the slots lie.
  struct Case {
    BmcLobe lobe;
    double m, tilt;
  };
  for (const Case c : {Case{BmcLobe::Gaussian, 20.0, 0.0}, Case{BmcLobe::Gaussian, 20.0, 50.0},
                       Case{BmcLobe::Gaussian, 80.0, 30.0}, Case{BmcLobe::Cosine, 1.0, 0.0}}) {
    const int n = 12;
    const double l = 1.25 / std::sqrt(c.m);
    const auto set = build_bmc_sample_set(c.lobe, n, c.m, l, 1e-5);
    const Vec3d axis = tilted(c.tilt);
    const BmcRule rule = bmc_rule(*set, axis, 0.37);
    ASSERT_EQ(rule.slots.size(), size_t(n));
    std::vector<double> coefficient(static_cast<size_t>(n));
    double sum = 0.0;
    for (int j = 0; j < n; ++j) sum += coefficient[size_t(j)] = std::sin(1.7 * j + 0.3);
    for (double& a : coefficient) a -= sum / n;
    const auto f = [&](const Vec3d& w) {
      double v = 0.8;
      for (int j = 0; j < n; ++j)
        v += coefficient[size_t(j)] * sg(rule.slots[size_t(j)], 1.0 / (l * l), w);
      return v;
    };
    const auto p = [&](const Vec3d& w) {
      return c.lobe == BmcLobe::Cosine ? w.z / kPiD : sg(axis, c.m, w);
    };
    const double exact = hemisphere_quadrature([&](const Vec3d& w) { return f(w) * p(w); });
    double estimate = 0.0;
    for (int j = 0; j < n; ++j) estimate += rule.slot_weights[size_t(j)] * f(rule.slots[size_t(j)]);
    EXPECT_NEAR(estimate, exact, 1e-6 * std::abs(exact)) << c.m << " " << c.tilt;
    EXPECT_NEAR(rule.lobe_integral, hemisphere_quadrature(p), 1e-9 * rule.lobe_integral);
  }
}

TEST(BmcQuadrature, ConstantRadianceIsExactUnderTheHorizon) {
  // At the fast rule's hyperparameters, Y = L̄ H gives Î = L̄ μ (Eq. 24), whatever the horizon
  // cuts off: the weights, folded onto the directions above the horizon, sum to μ.
  for (double tilt : {0.0, 45.0, 70.0, 85.0}) {
    const auto set = bmc_sample_set(BmcLobe::Gaussian, 40, 20.0, BmcHyperparameters{});
    const BmcRule rule = bmc_rule(*set, tilted(tilt), 0.81);
    double sum = 0.0;
    for (double w : rule.weights) sum += w;
    for (const Vec3d& d : rule.directions) EXPECT_GT(d.z, 0.0);
    const double mu = sg_hemisphere_moments(tilted(tilt).z, 20.0).area;
    EXPECT_NEAR(rule.lobe_integral, mu, 1e-14);
    EXPECT_NEAR(sum, mu, 1e-9 * mu) << tilt;
  }
  const auto cosine = bmc_sample_set(BmcLobe::Cosine, 64, 1.0, BmcHyperparameters{});
  double mean_weights = 0.0, sum = 0.0;
  for (double g : cosine->mean_weights) mean_weights += g;
  for (double w : bmc_rule(*cosine, Vec3d(0, 0, 1), 0.2).weights) sum += w;
  EXPECT_NEAR(mean_weights, 1.0, 1e-12);
  EXPECT_NEAR(sum, 1.0, 1e-9);
}

TEST(BmcQuadrature, FastRuleAndRandomRotation) {
  // [BMC] §5.4: σ'_n = 0.5 and l = 1.25/√m (m = 1 for the cosine lobe) unless told otherwise.
  const auto glossy = bmc_sample_set(BmcLobe::Gaussian, 16, 50.0, BmcHyperparameters{});
  EXPECT_NEAR(glossy->lengthscale, 1.25 / std::sqrt(50.0), 1e-15);
  EXPECT_EQ(glossy->noise, 0.5);
  EXPECT_NEAR(bmc_sample_set(BmcLobe::Cosine, 16, 1.0, BmcHyperparameters{})->lengthscale, 1.25,
              1e-15);
  EXPECT_NEAR(
      bmc_sample_set(BmcLobe::Gaussian, 16, 20.0, BmcHyperparameters{0.8, 2.0})->lengthscale,
      2.0 / std::sqrt(20.0), 1e-15);
  // Alg. 2, step 1: the rotation turns the whole pattern about the lobe's axis by 2π × rotation.
  const Vec3d axis = tilted(30.0);
  const BmcRule zero = bmc_rule(*glossy, axis, 0.0), turned = bmc_rule(*glossy, axis, 0.3);
  const double angle = 2.0 * kPiD * 0.3;
  for (size_t j = 0; j < zero.slots.size(); ++j) {
    const Vec3d& v = zero.slots[j];  // Rodrigues' rotation about the axis
    const Vec3d expected = v * std::cos(angle) + glm::cross(axis, v) * std::sin(angle) +
                           axis * glm::dot(axis, v) * (1.0 - std::cos(angle));
    EXPECT_NEAR(glm::length(turned.slots[j] - expected), 0.0, 1e-12) << j;
  }
}

namespace {

// A glossy lobe p = exp(m (ω·a − 1)) on the hemisphere, tilted from the normal, under an
// environment of one spherical Gaussian plus a constant: ∫_H L p in closed form through the
// product of the two spherical Gaussians.
struct SgScene {
  double m = 50.0;
  Vec3d a = tilted(35.0);
  Vec3d b = glm::normalize(tilted(35.0) + Vec3d(0.0, 0.2, 0.05));
  double kappa = 8.0, constant = 0.2;
  double radiance(const Vec3d& w) const { return sg(b, kappa, w) + constant; }
  double exact() const {
    const Vec3d v = b * kappa + a * m;
    const double k = glm::length(v);
    return std::exp(k - kappa - m) * sg_hemisphere_moments(v.z / k, k).area +
           constant * sg_hemisphere_moments(a.z, m).area;
  }
};

// Root-mean-square relative error over `trials` of BMC (random rotations of the pattern) and
// of Monte Carlo importance sampling of the lobe (independent directions, pdf ∝ the lobe on
// its hemisphere about a, directions under the horizon contributing zero).
double bmc_rmse(const SgScene& s, int n, int trials) {
  const auto set = bmc_sample_set(BmcLobe::Gaussian, n, s.m, BmcHyperparameters{});
  const double exact = s.exact();
  double sum2 = 0.0;
  for (int t = 0; t < trials; ++t) {
    const BmcRule rule = bmc_rule(*set, s.a, (t + 0.5) / trials);
    double estimate = 0.0;
    for (size_t j = 0; j < rule.directions.size(); ++j)
      estimate += rule.weights[j] * s.radiance(rule.directions[j]);
    sum2 += (estimate / exact - 1.0) * (estimate / exact - 1.0);
  }
  return std::sqrt(sum2 / trials);
}

double mc_rmse(const SgScene& s, int n, int trials) {
  const double exact = s.exact(), norm = 2.0 * kPiD * (1.0 - std::exp(-s.m)) / s.m;
  const Vec3d a = s.a, t1 = glm::normalize(glm::cross(a, Vec3d(0, 1, 0))), t2 = glm::cross(a, t1);
  double sum2 = 0.0;
  Rng rng(7, uint64_t(n));
  for (int t = 0; t < trials; ++t) {
    double estimate = 0.0;
    for (int j = 0; j < n; ++j) {
      const double u = rng.uniform(), phi = 2.0 * kPiD * rng.uniform();
      const double z = 1.0 + std::log(u + (1.0 - u) * std::exp(-s.m)) / s.m;
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      const Vec3d w = a * z + t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi));
      if (w.z > 0.0) estimate += s.radiance(w) * norm;  // p / pdf = the lobe's integral
    }
    estimate /= n;
    sum2 += (estimate / exact - 1.0) * (estimate / exact - 1.0);
  }
  return std::sqrt(sum2 / trials);
}

double fitted_slope(const std::vector<double>& n, const std::vector<double>& e) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double k = double(n.size());
  for (size_t i = 0; i < n.size(); ++i) {
    const double x = std::log(n[i]), y = std::log(e[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (k * sxy - sx * sy) / (k * sxx - sx * sx);
}

}  // namespace

TEST(BmcQuadrature, SphericalGaussianEnvironmentConvergesFasterThanImportanceSampling) {
  const SgScene scene;
  std::vector<double> ns, bmc, mc;
  for (int n : {16, 32, 64, 128, 256}) {
    ns.push_back(n);
    bmc.push_back(bmc_rmse(scene, n, 32));
    mc.push_back(mc_rmse(scene, n, 400));
  }
  const double bmc_slope = fitted_slope(ns, bmc), mc_slope = fitted_slope(ns, mc);
  for (size_t i = 0; i < ns.size(); ++i)
    std::printf("n %4.0f  BMC %.3e  MC %.3e\n", ns[i], bmc[i], mc[i]);
  std::printf("slopes: BMC %.2f, MC %.2f\n", bmc_slope, mc_slope);
  EXPECT_LT(bmc.back(), 0.01);
  EXPECT_LT(bmc_slope, -0.6);
  EXPECT_NEAR(mc_slope, -0.5, 0.1);
  for (size_t i = 0; i < ns.size(); ++i) EXPECT_LT(bmc[i], mc[i]) << ns[i];
}

namespace {

// A large plane (y = 0) of `bsdf` under a constant sky of radiance 1.
std::unique_ptr<Scene> plane_under_sky(BsdfPtr bsdf) {
  SceneDescription d;
  d.source = "plane-under-sky";
  const int material = test::add_material(d, std::move(bsdf));
  test::add_quad(d, Vec3(-100, 0, -100), Vec3(-100, 0, 100), Vec3(100, 0, 100), Vec3(100, 0, -100),
                 material);
  d.environment.kind = EnvironmentDesc::Kind::Constant;
  d.environment.radiance = Rgb(1.0f);
  d.camera = test::camera_at(Vec3(0, 2, 0), Vec3(0.1f, 0, 0.1f), 8, Vec3(0, 0, 1));
  return Scene::build(std::move(d));
}

}  // namespace

TEST(BmcDirect, FurnaceThroughTheDirectIntegrator) {
  // A Lambertian plane under a constant sky reflects its albedo exactly: the cosine lobe is
  // modelled exactly and constant radiance is exact for the rule.
  RenderSettings s;
  s.spp = 1;
  s.direct_samples = 8;
  s.direct_point_set = DirectPointSet::Bmc;
  const auto lambertian = plane_under_sky(make_lambertian(Rgb(0.7f)));
  const Image diffuse = test::render(DirectIntegrator(), *lambertian, s);
  for (const Rgb& p : diffuse.pixels) EXPECT_NEAR(p.y, 0.7f, 2e-5f);

  // Normalised Phong seen along the normal reflects kd + ks; the Gaussian lobe stands for
  // cos^n times the cosine only approximately, so the rule converges rather than being exact.
  const auto phong = plane_under_sky(make_phong(40.0f, Rgb(0.6f), Rgb(0.3f)));
  SurfaceHit hit;
  ASSERT_TRUE(phong->intersect(Ray{Vec3(0, 1, 0), Vec3(0, -1, 0)}, hit));
  double previous = 1.0;
  for (int samples : {16, 64, 256}) {
    DirectLightingOptions options;
    options.samples = samples;
    options.point_set = DirectPointSet::Bmc;
    double sum2 = 0.0;
    for (int t = 0; t < 8; ++t) {
      Rng rng(3, uint64_t(t));
      const double e = estimate_direct_lighting(*phong, hit, Vec3(0, 1, 0), rng, options).y - 0.9;
      sum2 += e * e;
    }
    const double rmse = std::sqrt(sum2 / 8.0);
    std::printf("phong furnace, %d directions: RMSE %.2e\n", 2 * samples, rmse);
    EXPECT_LT(rmse, previous);
    previous = rmse;
  }
  EXPECT_LT(previous, 2e-3);
}
