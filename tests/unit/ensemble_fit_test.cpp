// The anisotropic kernel's fit (eq. 11-12) against the textbook weighted covariance: the
// detailed-balance tests pass for any deterministic covariance, so they cannot tell a wrong
// scatter from a right one; this test can.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "emlt/core/rng.h"
#include "mutations/ensemble/kernels.h"

namespace emlt::ensemble {
namespace {

// Σ of the guides projected on the plane (axes from the fit), reliability weights.
struct Covariance {
  double ss = 0.0, st = 0.0, tt = 0.0;
};

Covariance direct_covariance(const TangentGaussian& plane, const std::vector<Vec3>& points,
                             const std::vector<double>& weights) {
  double total = 0.0, squares = 0.0, mean_s = 0.0, mean_t = 0.0;
  std::vector<double> s(points.size()), t(points.size());
  for (size_t n = 0; n < points.size(); ++n) {
    const DVec3 offset = DVec3(points[n]) - plane.centre;
    s[n] = glm::dot(offset, plane.axis_s);
    t[n] = glm::dot(offset, plane.axis_t);
    total += weights[n];
    squares += weights[n] * weights[n];
    mean_s += weights[n] * s[n];
    mean_t += weights[n] * t[n];
  }
  mean_s /= total;
  mean_t /= total;
  Covariance c;
  for (size_t n = 0; n < points.size(); ++n) {
    c.ss += weights[n] * (s[n] - mean_s) * (s[n] - mean_s);
    c.st += weights[n] * (s[n] - mean_s) * (t[n] - mean_t);
    c.tt += weights[n] * (t[n] - mean_t) * (t[n] - mean_t);
  }
  const double normaliser = total - squares / total;
  c.ss /= normaliser;
  c.st /= normaliser;
  c.tt /= normaliser;
  return c;
}

TEST(EnsembleFit, CovarianceIsTheWeightedCovarianceOfTheProjectedGuides) {
  Rng rng(5, 0);
  AnisotropicParams params;
  params.covariance_scale = 1.0;
  params.floor_sigma = 0.0;
  params.min_effective_guides = 1.0;
  params.similarity.length_scale = 3.0;
  for (int trial = 0; trial < 40; ++trial) {
    // Guides far from the centre compared with their spread (where a one-pass sum of squares
    // cancels), on a tilted plane; odd counts leave a tail after the pairs.
    const size_t count = 3 + size_t(trial) % 8;
    const Vec3 centre(100.0f * rng.uniform(), 50.0f, -20.0f * rng.uniform());
    const Vec3 normal = glm::normalize(Vec3(rng.uniform() - 0.5f, 1.0f, rng.uniform() - 0.5f));
    const Vec3 cluster = centre + Vec3(30.0f, 0.5f, -10.0f);
    std::vector<Vec3> points(count);
    std::vector<double> x(count), y(count), z(count), context(count), to_centre(count);
    for (size_t n = 0; n < count; ++n) {
      points[n] = cluster + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 0.3f;
      x[n] = points[n].x, y[n] = points[n].y, z[n] = points[n].z;
      context[n] = 0.05 + rng.uniform();
      to_centre[n] = vertex_similarity(centre, points[n], params.similarity);
    }
    std::vector<double> weights(count);
    for (size_t n = 0; n < count; ++n) weights[n] = context[n] * to_centre[n];

    // As the anisotropic path perturbation passes them (coordinate arrays and rows), and as
    // points with the centre's similarity computed by the fit.
    const GuideSet arrays{{}, {}, {}, to_centre, context, x, y, z};
    const GuideSet as_points{points, {}, {}, {}, context};
    for (const GuideSet* set : {&arrays, &as_points}) {
      const TangentGaussian fit = fit_tangent_gaussian(centre, normal, *set, params);
      ASSERT_FALSE(fit.fallback);
      const Covariance expected = direct_covariance(fit, points, weights);
      const double scale = expected.ss + expected.tt;
      EXPECT_NEAR(fit.covariance.ss, expected.ss, 1e-9 * scale) << trial;
      EXPECT_NEAR(fit.covariance.st, expected.st, 1e-9 * scale) << trial;
      EXPECT_NEAR(fit.covariance.tt, expected.tt, 1e-9 * scale) << trial;
      double sum = 0.0, squares = 0.0;
      for (const double w : weights) sum += w, squares += w * w;
      EXPECT_NEAR(fit.effective_guides, sum * sum / squares, 1e-12 * count) << trial;
      // Eq. 11 as printed: the same scatter over (M - 1) with normalised weights, that is
      // the reliability-weighted covariance times (total - squares / total) / ((M - 1) total).
      AnisotropicParams printed = params;
      printed.printed_normalisation = true;
      const TangentGaussian literal = fit_tangent_gaussian(centre, normal, *set, printed);
      ASSERT_FALSE(literal.fallback);
      const double factor = (sum - squares / sum) / (double(count - 1) * sum);
      EXPECT_NEAR(literal.covariance.ss, expected.ss * factor, 1e-9 * scale) << trial;
      EXPECT_NEAR(literal.covariance.st, expected.st * factor, 1e-9 * scale) << trial;
      EXPECT_NEAR(literal.covariance.tt, expected.tt * factor, 1e-9 * scale) << trial;
    }
  }
}

// Without guides the fit falls back to the isotropic Gaussian of the parameter's width. Its
// shape is kept per thread for the last width, so widths alternate here: a stale shape, or
// any fixed one, would keep detailed balance (the chain tests cannot see it) but not this.
TEST(EnsembleFit, FallbackIsTheIsotropicGaussianOfTheParametersWidth) {
  const GuideSet none{};
  const Vec3 centre(1.0f, 2.0f, 3.0f), normal(0.0f, 1.0f, 0.0f);
  for (const double sigma : {0.05, 0.2, 0.05, 0.01, 0.2}) {
    AnisotropicParams params;
    params.fallback_sigma = sigma;
    const TangentGaussian fit = fit_tangent_gaussian(centre, normal, none, params);
    ASSERT_TRUE(fit.fallback);
    const double variance = sigma * sigma;
    EXPECT_DOUBLE_EQ(fit.covariance.ss, variance) << sigma;
    EXPECT_EQ(fit.covariance.st, 0.0) << sigma;
    EXPECT_DOUBLE_EQ(fit.covariance.tt, variance) << sigma;
    EXPECT_DOUBLE_EQ(fit.covariance.chol_ss, sigma) << sigma;
    EXPECT_DOUBLE_EQ(fit.covariance.chol_tt, sigma) << sigma;
    EXPECT_DOUBLE_EQ(fit.covariance.normaliser, 1.0 / (2.0 * 3.14159265358979323846 * variance))
        << sigma;
  }
}

// The vMF's normaliser is kept per thread for the last concentration; concentrations
// alternate here, and both forms must be the textbook density
// kappa / (2 pi (1 - e^(-2 kappa))) e^(kappa (cos - 1)) every time.
TEST(EnsembleFit, VmfDensityFollowsEachConcentration) {
  for (const double kappa : {5.0, 200.0, 5.0, 0.5, 200.0, 0.5}) {
    for (const double cosine : {1.0, 0.3, -0.8}) {
      const double expected = kappa /
                              (2.0 * 3.14159265358979323846 * (1.0 - std::exp(-2.0 * kappa))) *
                              std::exp(kappa * (cosine - 1.0));
      EXPECT_NEAR(std::exp(vmf_log_pdf(kappa, cosine)), expected, 1e-12 * expected) << kappa;
      const DensityParts parts = vmf_pdf_parts(kappa, cosine);
      EXPECT_NEAR(parts.factor * std::exp(parts.exponent), expected, 1e-12 * expected) << kappa;
    }
  }
}

}  // namespace
}  // namespace emlt::ensemble
