// Area-light sampling (the checks T-LIGHT-1 and T-LIGHT-2) and light selection.
// Every Monte Carlo check uses a fixed seed and a 4-sigma (or chi-square p) criterion.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/scene/environment.h"
#include "emlt/scene/light.h"
#include "emlt/scene/light_set.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

// Barycentric (b1, b2) of p with respect to triangle (a, b, c): p = a + b1 (b-a) + b2 (c-a).
Vec2 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const DVec3 e1 = DVec3(b - a), e2 = DVec3(c - a), d = DVec3(p - a);
  const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const double r1 = glm::dot(d, e1), r2 = glm::dot(d, e2);
  const double det = d11 * d22 - d12 * d12;
  return {float((d22 * r1 - d12 * r2) / det), float((d11 * r2 - d12 * r1) / det)};
}

// Splits the triangle into n^2 congruent sub-triangles (equal areas) and returns the cell
// holding barycentric (b1, b2).
int barycentric_cell(const Vec2& bary, int n) {
  const double s = std::clamp(double(bary.x), 0.0, 1.0) * n;
  const double t = std::clamp(double(bary.y), 0.0, 1.0) * n;
  const int i = std::min(int(s), n - 1), j = std::min(int(t), n - 1);
  const bool upper = (s - i) + (t - j) > 1.0;
  // Cells (i, j, lower) exist for i + j <= n - 1, (i, j, upper) for i + j <= n - 2.
  return std::min((i * n + j) * 2 + (upper ? 1 : 0), 2 * n * n - 1);
}

// Form factor from a differential area to a parallel a x b rectangle whose corner lies on
// the area's normal at height h (Howell's catalogue, configuration B-3).
double corner_rectangle_form_factor(double a, double b, double h) {
  const double x = a / h, y = b / h;
  const double sx = std::sqrt(1.0 + x * x), sy = std::sqrt(1.0 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2.0 * M_PI);
}

}  // namespace

// Uniform area sampling: chi-square over equal-area barycentric cells of a skewed triangle.
TEST(TriangleLight, SampledPointsAreUniformOverTheTriangle) {
  const Vec3 a(0.2f, -0.3f, 1.0f), b(2.5f, 0.1f, 1.4f), c(0.7f, 1.9f, 0.8f);
  const TriangleLight light(a, b, c, Rgb(1.0f));
  const Vec3 ref = (a + b + c) / 3.0f + 3.0f * light.normal();  // in front of the emitter
  const int n = 8, samples = 200000;
  std::vector<double> observed(2 * n * n, 0.0), expected(2 * n * n, 0.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (i + j <= n - 1) expected[(i * n + j) * 2] = double(samples) / (n * n);
      if (i + j <= n - 2) expected[(i * n + j) * 2 + 1] = double(samples) / (n * n);
    }
  }
  Rng rng(11, 0);
  for (int k = 0; k < samples; ++k) {
    const auto s = light.sample_direct(ref, rng.uniform2());
    ASSERT_TRUE(s.has_value());
    const Vec2 bary = barycentric(s->position, a, b, c);
    ASSERT_GE(bary.x, -1e-4f);
    ASSERT_GE(bary.y, -1e-4f);
    ASSERT_LE(bary.x + bary.y, 1.0f + 1e-4f);
    observed[barycentric_cell(bary, n)] += 1.0;
  }
  const auto result = test::chi_square_test(observed, expected);
  EXPECT_GT(result.p_value, 1e-3) << "chi2 " << result.statistic << " dof "
                                  << result.degrees_of_freedom;
}

// The sample's solid-angle pdf equals pdf_direct() and the d^2 / (cos * area) conversion;
// receivers behind the one-sided emitter get nothing.
TEST(TriangleLight, DirectPdfIsTheSolidAngleConversionOfTheAreaDensity) {
  const Vec3 a(-1.0f, 2.0f, -1.0f), b(1.0f, 2.0f, -1.0f), c(0.0f, 2.0f, 1.0f);
  const TriangleLight light(a, b, c, Rgb(2.0f, 3.0f, 4.0f));
  ASSERT_NEAR(light.area(), 2.0f, 1e-6f);
  ASSERT_NEAR(light.normal().y, -1.0f, 1e-6f);  // cross(b-a, c-a) points down to y < 2
  EXPECT_NEAR(luminance(light.power()), kPi * 2.0f * luminance(Rgb(2.0f, 3.0f, 4.0f)), 1e-4f);

  Rng rng(12, 0);
  int checked = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 ref(4.0f * rng.uniform() - 2.0f, 1.9f - 3.0f * rng.uniform(),
                   4.0f * rng.uniform() - 2.0f);
    const auto s = light.sample_direct(ref, rng.uniform2());
    ASSERT_TRUE(s.has_value());
    const Vec3 to = s->position - ref;
    const double d2 = glm::dot(DVec3(to), DVec3(to));
    const double cos_light = -glm::dot(DVec3(light.normal()), DVec3(to)) / std::sqrt(d2);
    const double expected_pdf = d2 / (cos_light * 2.0);
    EXPECT_NEAR(s->pdf, expected_pdf, 1e-4 * expected_pdf);
    EXPECT_NEAR(light.pdf_direct(ref, s->position, s->normal, s->wi), s->pdf, 1e-5f * s->pdf);
    EXPECT_NEAR(s->distance, std::sqrt(d2), 1e-5 * std::sqrt(d2));
    EXPECT_EQ(s->radiance, Rgb(2.0f, 3.0f, 4.0f));
    EXPECT_EQ(light.emitted(s->normal, -s->wi), Rgb(2.0f, 3.0f, 4.0f));
    EXPECT_EQ(light.emitted(s->normal, s->wi), Rgb(0.0f));
    ++checked;
  }
  EXPECT_EQ(checked, 20000);

  // Behind the emitting side, and in its plane: no sample, zero density.
  const Vec3 behind(0.0f, 3.0f, 0.0f);
  for (int k = 0; k < 100; ++k) {
    EXPECT_FALSE(light.sample_direct(behind, rng.uniform2()).has_value());
  }
  const Vec3 p(0.0f, 2.0f, 0.0f);
  EXPECT_EQ(light.pdf_direct(behind, p, light.normal(), glm::normalize(p - behind)), 0.0f);
  EXPECT_FALSE(light.sample_direct(Vec3(5.0f, 2.0f, 0.0f), Vec2(0.3f, 0.4f)).has_value());
  EXPECT_EQ(light.pdf_direct(p, p, light.normal(), Vec3(0.0f, 1.0f, 0.0f)), 0.0f);

  // A degenerate triangle has no power and never samples.
  const TriangleLight sliver(a, b, a, Rgb(1.0f));
  EXPECT_EQ(luminance(sliver.power()), 0.0f);
  EXPECT_FALSE(sliver.sample_direct(Vec3(0.0f), Vec2(0.5f)).has_value());
}

// Irradiance at a point below a unit square emitter (two triangles picked through a
// LightSet) against the analytic form factor, on-axis and under a corner.
TEST(TriangleLight, IrradianceFromASquareMatchesTheFormFactor) {
  const float h = 1.0f, radiance = 3.0f;
  // Square [-0.5,0.5]^2 at z = h, wound so the normal points down (-z) to the receiver.
  const Vec3 p00(-0.5f, -0.5f, h), p10(0.5f, -0.5f, h), p11(0.5f, 0.5f, h), p01(-0.5f, 0.5f, h);
  std::vector<LightPtr> lights;
  lights.push_back(std::make_unique<TriangleLight>(p00, p11, p10, Rgb(radiance)));
  lights.push_back(std::make_unique<TriangleLight>(p00, p01, p11, Rgb(radiance)));
  ASSERT_LT(static_cast<const TriangleLight&>(*lights[0]).normal().z, -0.99f);
  ASSERT_LT(static_cast<const TriangleLight&>(*lights[1]).normal().z, -0.99f);
  const LightSet set(std::move(lights));

  struct Case {
    Vec3 receiver;
    double exact;
  };
  const Case cases[] = {
      {Vec3(0.0f), radiance * M_PI * 4.0 * corner_rectangle_form_factor(0.5, 0.5, h)},
      {Vec3(-0.5f, -0.5f, 0.0f), radiance * M_PI * corner_rectangle_form_factor(1.0, 1.0, h)},
  };
  Rng rng(13, 0);
  const int samples = 200000;
  for (const Case& c : cases) {
    double sum = 0.0, sum_sq = 0.0;
    for (int k = 0; k < samples; ++k) {
      float pick = 0.0f;
      const Light* light = set.choose(rng.uniform(), &pick);
      ASSERT_NE(light, nullptr);
      const Vec2 u = rng.uniform2();
      const auto s = light->sample_direct(c.receiver, u);
      double value = 0.0;
      if (s) value = luminance(s->radiance) * std::max(0.0f, s->wi.z) / (s->pdf * pick);
      sum += value;
      sum_sq += value * value;
    }
    const double mean = sum / samples;
    const double sigma = std::sqrt(std::max(0.0, sum_sq / samples - mean * mean) / samples);
    EXPECT_NEAR(mean, c.exact, 0.02 * c.exact);
    EXPECT_NEAR(mean, c.exact, 4.0 * sigma + 1e-6 * c.exact) << "sigma " << sigma;
  }
}

// Emission: the pdfs of a sample agree with pdf_emission(), the origin lies on the
// triangle, and directions are cosine distributed (cos^2 theta and phi uniform).
TEST(TriangleLight, EmissionSamplesAreCosineDistributedAndMatchPdfEmission) {
  const Vec3 a(0.0f, 0.0f, 0.0f), b(2.0f, 0.0f, 0.0f), c(0.0f, 1.0f, 1.0f);
  const TriangleLight light(a, b, c, Rgb(1.5f));
  const Vec3 n = light.normal();
  const Vec3 s_axis = glm::normalize(b - a), t_axis = glm::cross(n, s_axis);
  const int bins = 10, samples = 200000;
  std::vector<double> observed(bins * bins, 0.0);
  const std::vector<double> expected(bins * bins, double(samples) / (bins * bins));
  double flux_sum = 0.0;
  Rng rng(14, 0);
  for (int k = 0; k < samples; ++k) {
    const auto e = light.sample_emission(rng.uniform2(), rng.uniform2());
    ASSERT_TRUE(e.has_value());
    const Vec3 w = e->ray.direction;
    ASSERT_NEAR(glm::length(w), 1.0f, 1e-5f);
    const float cos_theta = glm::dot(w, n);
    ASSERT_GT(cos_theta, 0.0f);
    // The origin is on the triangle (up to the spawn offset along the normal).
    ASSERT_LT(std::abs(glm::dot(e->ray.origin - a, n)), 1e-3f);
    const Vec2 bary = barycentric(e->ray.origin, a, b, c);
    ASSERT_GE(std::min(bary.x, bary.y), -1e-3f);
    ASSERT_LE(bary.x + bary.y, 1.0f + 1e-3f);
    float pdf_position = 0.0f, pdf_direction = 0.0f;
    light.pdf_emission(e->ray.origin, e->normal, w, &pdf_position, &pdf_direction);
    ASSERT_NEAR(pdf_position, e->pdf_position, 1e-6f * e->pdf_position);
    ASSERT_NEAR(pdf_direction, e->pdf_direction, 1e-5f * e->pdf_direction + 1e-7f);
    ASSERT_NEAR(e->pdf_direction, cos_theta * kInvPi, 1e-5f);
    ASSERT_NEAR(e->pdf_position, 1.0f / light.area(), 1e-6f);
    flux_sum += luminance(e->radiance) * cos_theta / (e->pdf_position * e->pdf_direction);
    const double phi = std::atan2(glm::dot(w, t_axis), glm::dot(w, s_axis)) + M_PI;
    const int i = std::min(int(cos_theta * cos_theta * bins), bins - 1);
    const int j = std::min(int(phi / (2.0 * M_PI) * bins), bins - 1);
    observed[i * bins + j] += 1.0;
  }
  const auto result = test::chi_square_test(observed, expected);
  EXPECT_GT(result.p_value, 1e-3) << "chi2 " << result.statistic;
  // Cosine sampling makes the flux estimator exact: every sample returns pi * A * L.
  EXPECT_NEAR(flux_sum / samples, luminance(light.power()), 1e-4 * luminance(light.power()));
  float pp = 1.0f, pd = 1.0f;
  light.pdf_emission(a, n, -n, &pp, &pd);
  EXPECT_EQ(pd, 0.0f);  // nothing is emitted from the back face
}

// T-LIGHT-1: selection in proportion to luminous power, consistent probabilities, zero-power
// lights never chosen, indices assigned, the environment found.
TEST(LightSet, ChoosesLightsInProportionToPower) {
  const Rgb radiances[] = {Rgb(1.0f), Rgb(4.0f, 2.0f, 1.0f), Rgb(0.0f), Rgb(0.5f, 0.5f, 3.0f)};
  const float scales[] = {1.0f, 0.5f, 2.0f, 1.5f};
  std::vector<LightPtr> lights;
  std::vector<double> expected_power;
  for (int i = 0; i < 4; ++i) {
    const float s = scales[i];
    lights.push_back(std::make_unique<TriangleLight>(Vec3(0.0f), Vec3(s, 0.0f, 0.0f),
                                                     Vec3(0.0f, s, 0.0f), radiances[i]));
    expected_power.push_back(M_PI * 0.5 * s * s * luminance(radiances[i]));
  }
  auto sky = std::make_unique<ConstantEnvironment>(Rgb(0.02f));
  sky->set_scene_bounds(Vec3(0.0f), 1.5f);
  expected_power.push_back(M_PI * 1.5 * 1.5 * 4.0 * M_PI * 0.02);
  const Light* sky_ptr = sky.get();
  lights.insert(lights.begin() + 2, std::move(sky));
  expected_power.insert(expected_power.begin() + 2, expected_power.back());
  expected_power.pop_back();
  const LightSet set(std::move(lights));
  ASSERT_EQ(set.size(), 5u);
  EXPECT_EQ(set.environment(), sky_ptr);

  double total_power = 0.0;
  for (double p : expected_power) total_power += p;
  double probability_sum = 0.0;
  for (size_t i = 0; i < set.size(); ++i) {
    EXPECT_EQ(set.light(i).index, int(i));
    const float p = set.selection_probability(set.light(i));
    EXPECT_NEAR(p, expected_power[i] / total_power, 1e-5);
    probability_sum += p;
  }
  EXPECT_NEAR(probability_sum, 1.0, 1e-6);
  const size_t black = 3;  // the zero-radiance triangle, after the sky's insertion
  EXPECT_EQ(set.selection_probability(set.light(black)), 0.0f);

  const int samples = 200000;
  std::vector<double> observed(set.size(), 0.0), expected(set.size(), 0.0);
  for (size_t i = 0; i < set.size(); ++i) expected[i] = samples * expected_power[i] / total_power;
  Rng rng(15, 0);
  for (int k = 0; k < samples; ++k) {
    float p = 0.0f;
    const Light* light = set.choose(rng.uniform(), &p);
    ASSERT_NE(light, nullptr);
    ASSERT_NE(size_t(light->index), black);
    ASSERT_EQ(p, set.selection_probability(*light));
    observed[size_t(light->index)] += 1.0;
  }
  // Extreme u values stay on positive-power lights too.
  for (float u : {0.0f, 1e-9f, 0.5f, kOneMinusEpsilon}) {
    float p = 0.0f;
    const Light* light = set.choose(u, &p);
    ASSERT_NE(light, nullptr);
    EXPECT_GT(p, 0.0f);
  }
  const auto result = test::chi_square_test(observed, expected);
  EXPECT_GT(result.p_value, 1e-3) << "chi2 " << result.statistic;

  // A light that is not in the set has selection probability 0, even with a valid index.
  TriangleLight stranger(Vec3(0.0f), Vec3(1.0f, 0.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f), Rgb(1.0f));
  stranger.index = 0;
  EXPECT_EQ(set.selection_probability(stranger), 0.0f);
}

TEST(LightSet, EmptyOrBlackSetsChooseNothing) {
  const LightSet empty;
  float p = 1.0f;
  EXPECT_EQ(empty.choose(0.5f, &p), nullptr);
  EXPECT_EQ(p, 0.0f);
  EXPECT_EQ(empty.environment(), nullptr);

  std::vector<LightPtr> lights;
  lights.push_back(std::make_unique<TriangleLight>(Vec3(0.0f), Vec3(1.0f, 0.0f, 0.0f),
                                                   Vec3(0.0f, 1.0f, 0.0f), Rgb(0.0f)));
  const LightSet black(std::move(lights));
  p = 1.0f;
  EXPECT_EQ(black.choose(0.3f, &p), nullptr);
  EXPECT_EQ(p, 0.0f);
  EXPECT_EQ(black.selection_probability(black.light(0)), 0.0f);
}
