// Environment sampling (seed-lights.md §6.1-6.4: T-ENV-1..5 and the §6.4 variance figures).
// Maps are synthesised here; the test keeps its own copy of the texel table so that the
// pdf is checked against the formula, not only against itself.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/core/warp.h"
#include "emlt/scene/environment.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// Smooth colours, two bright blobs and a black block of columns (zero probability).
Image smooth_map() {
  Image map(64, 32);
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const float u = (x + 0.5f) / map.width, v = (y + 0.5f) / map.height;
      Rgb value(0.2f + u, 0.5f + 0.4f * std::sin(6.0f * v), 0.3f + v * v);
      if (x >= 20 && x < 26 && y >= 6 && y < 10) value *= 30.0f;
      if (x >= 50 && x < 52 && y >= 25 && y < 29) value *= 80.0f;
      if (x >= 36 && x < 42) value = Rgb(0.0f);
      map.at(x, y) = value;
    }
  }
  return map;
}

// Sky of radiance 1 plus a sun lobe L_sun max(0, w.w_sun)^100 with L_sun = 1e5 (the sun
// peaks 1e5 x above the sky), 45 degrees above the horizon, rasterised at texel centres.
const Vec3 kSunDirection = glm::normalize(Vec3(0.6f, 1.0f, -0.8f));

Image sun_sky_map() {
  Image map(128, 64);
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const Vec3 w = latlong_to_direction(Vec2((x + 0.5f) / map.width, (y + 0.5f) / map.height));
      const float lobe = std::pow(std::max(0.0f, glm::dot(w, kSunDirection)), 100.0f);
      map.at(x, y) = Rgb(1.0f) + 1e5f * lobe * Rgb(1.0f, 0.9f, 0.7f);
    }
  }
  return map;
}

// The test's own texel table: P_ij proportional to luminance x sin(theta_centre), and the
// solid-angle pdf P_ij W H / (2 pi^2 sin theta) of the lat-long parametrisation.
struct ReferenceTable {
  int width, height;
  std::vector<double> probability;

  ReferenceTable(const Image& map, float scale, bool with_sin_theta = true)
      : width(map.width), height(map.height), probability(map.pixels.size()) {
    double total = 0.0;
    for (int y = 0; y < height; ++y) {
      const double sin_theta = std::sin(kPiD * (y + 0.5) / height);
      for (int x = 0; x < width; ++x) {
        const double w = luminance(scale * map.at(x, y)) * (with_sin_theta ? sin_theta : 1.0);
        probability[size_t(y) * width + x] = w;
        total += w;
      }
    }
    for (double& p : probability) p /= total;
  }
  double pdf(const Vec3& w) const {
    const Vec2 uv = direction_to_latlong(w);
    const int x = std::min(int(uv.x * width), width - 1), y = std::min(int(uv.y * height), height - 1);
    const double sin_theta = std::sqrt(double(w.x) * w.x + double(w.z) * w.z);
    return probability[size_t(y) * width + x] * width * height / (2.0 * kPiD * kPiD * sin_theta);
  }
};

// Probability of each (phi, cos theta) cell when every texel carries `texel_mass`
// spread uniformly over its (u, v) rectangle. Exact: cells and texels are both rectangles
// in (u, v) once cos theta is mapped to v = acos(cos theta) / pi.
std::vector<double> cell_probabilities(const std::vector<double>& texel_mass, int width,
                                       int height, int phi_bins, int cos_bins) {
  std::vector<double> cells(size_t(phi_bins) * cos_bins, 0.0);
  for (int j = 0; j < cos_bins; ++j) {
    // cos bin j covers cos theta in [1 - 2(j+1)/n, 1 - 2j/n]: v from acos(top) to acos(bottom).
    const double v0 = std::acos(1.0 - 2.0 * j / cos_bins) / kPiD;
    const double v1 = std::acos(std::max(-1.0, 1.0 - 2.0 * (j + 1) / cos_bins)) / kPiD;
    for (int y = 0; y < height; ++y) {
      const double overlap_v = std::max(0.0, std::min(v1, (y + 1.0) / height) -
                                                 std::max(v0, double(y) / height));
      if (overlap_v <= 0.0) continue;
      for (int i = 0; i < phi_bins; ++i) {
        const double u0 = double(i) / phi_bins, u1 = (i + 1.0) / phi_bins;
        for (int x = 0; x < width; ++x) {
          const double overlap_u =
              std::max(0.0, std::min(u1, (x + 1.0) / width) - std::max(u0, double(x) / width));
          if (overlap_u <= 0.0) continue;
          cells[size_t(j) * phi_bins + i] +=
              texel_mass[size_t(y) * width + x] * overlap_u * overlap_v * width * height;
        }
      }
    }
  }
  return cells;
}

int direction_cell(const Vec3& w, int phi_bins, int cos_bins) {
  const Vec2 uv = direction_to_latlong(w);
  const int i = std::min(int(uv.x * phi_bins), phi_bins - 1);
  const int j = std::clamp(int((1.0f - w.y) * 0.5f * cos_bins), 0, cos_bins - 1);
  return j * phi_bins + i;
}

}  // namespace

// T-ENV-1: the table's texel masses (recovered from pdf_direction at texel centres) sum to
// 1, and E[4 pi pdf] over uniform directions is 1.
TEST(EnvironmentMap, PdfIntegratesToOne) {
  for (const Image& image : {smooth_map(), sun_sky_map()}) {
    const EnvironmentMap env(image, 2.0f, Mat3(1.0f));
    double texel_sum = 0.0;
    for (int y = 0; y < image.height; ++y) {
      const double sin_theta = std::sin(kPiD * (y + 0.5) / image.height);
      for (int x = 0; x < image.width; ++x) {
        const Vec3 w = latlong_to_direction(
            Vec2((x + 0.5f) / image.width, (y + 0.5f) / image.height));
        texel_sum += env.pdf_direction(w) * 2.0 * kPiD * kPiD * sin_theta /
                     (double(image.width) * image.height);
      }
    }
    EXPECT_NEAR(texel_sum, 1.0, 1e-4);

    Rng rng(21, 0);
    const int samples = 400000;
    double sum = 0.0, sum_sq = 0.0;
    for (int k = 0; k < samples; ++k) {
      const double value = 4.0 * kPiD * env.pdf_direction(square_to_uniform_sphere(rng.uniform2()));
      ASSERT_TRUE(std::isfinite(value));
      sum += value;
      sum_sq += value * value;
    }
    const double mean = sum / samples;
    const double sigma = std::sqrt((sum_sq / samples - mean * mean) / samples);
    EXPECT_NEAR(mean, 1.0, 4.0 * sigma) << "sigma " << sigma;
  }
}

// T-ENV-2: every sample's pdf equals pdf_direction() and the independent table formula;
// samples never land on black texels; poles and the phi seam give finite values.
TEST(EnvironmentMap, SampledPdfEqualsEvaluatedPdf) {
  for (const Image& image : {smooth_map(), sun_sky_map()}) {
    const EnvironmentMap env(image, 1.0f, Mat3(1.0f));
    const ReferenceTable table(image, 1.0f);
    Rng rng(22, 0);
    for (int k = 0; k < 100000; ++k) {
      float pdf = 0.0f;
      const Vec3 w = env.sample_direction(rng.uniform2(), &pdf);
      ASSERT_NEAR(glm::length(w), 1.0f, 1e-5f);
      ASSERT_GT(pdf, 0.0f);
      ASSERT_NEAR(pdf, env.pdf_direction(w), 1e-3f * pdf);
      ASSERT_NEAR(pdf, table.pdf(w), 1e-3 * table.pdf(w)) << "sample " << k;
      ASSERT_GT(luminance(env.radiance(w)), 0.0f);  // never a black texel
    }
    // Near the poles, across the phi = 0 seam, on texel edges.
    for (float theta : {1e-3f, 0.02f, 1.0f, kPi - 0.02f, kPi - 1e-3f}) {
      for (float phi : {0.0f, 1e-6f, kTwoPi - 1e-6f, kTwoPi * 10.0f / 64.0f, 2.0f}) {
        const Vec3 w(std::sin(theta) * std::sin(phi), std::cos(theta),
                     -std::sin(theta) * std::cos(phi));
        const float pdf = env.pdf_direction(w);
        ASSERT_TRUE(std::isfinite(pdf));
        EXPECT_NEAR(pdf, table.pdf(w), 2e-3 * table.pdf(w)) << theta << " " << phi;
      }
    }
    EXPECT_EQ(env.pdf_direction(Vec3(0.0f, 1.0f, 0.0f)), 0.0f);
    EXPECT_EQ(env.pdf_direction(Vec3(0.0f, -1.0f, 0.0f)), 0.0f);
  }
  // A direction on a black texel of the smooth map has zero density.
  const EnvironmentMap smooth(smooth_map(), 1.0f, Mat3(1.0f));
  const Vec3 black = latlong_to_direction(Vec2(38.5f / 64.0f, 0.5f));
  EXPECT_EQ(smooth.pdf_direction(black), 0.0f);
  EXPECT_EQ(smooth.radiance(black), Rgb(0.0f));
}

// T-ENV-3: chi-square of 10^6 sampled directions over (phi, cos theta) cells against the
// integral of the pdf over each cell. The same histogram must reject the distribution
// whose measure drops sin(theta) (texel weights by luminance alone).
TEST(EnvironmentMap, ChiSquareOverSolidAngleCells) {
  const int phi_bins = 32, cos_bins = 16, samples = 1000000;
  for (const Image& image : {smooth_map(), sun_sky_map()}) {
    const EnvironmentMap env(image, 1.0f, Mat3(1.0f));
    // Texel masses from the evaluated pdf: pdf_uv = pdf_omega * 2 pi^2 sin(theta), constant
    // over the texel, so its value at the centre times the texel's (u,v) area is the mass.
    std::vector<double> mass(image.pixels.size()), mass_without_sin(image.pixels.size());
    double total_without_sin = 0.0;
    for (int y = 0; y < image.height; ++y) {
      const double sin_theta = std::sin(kPiD * (y + 0.5) / image.height);
      for (int x = 0; x < image.width; ++x) {
        const Vec3 w = latlong_to_direction(
            Vec2((x + 0.5f) / image.width, (y + 0.5f) / image.height));
        const double pdf = env.pdf_direction(w);
        const size_t at = size_t(y) * image.width + x;
        mass[at] = pdf * 2.0 * kPiD * kPiD * sin_theta / (double(image.width) * image.height);
        mass_without_sin[at] = pdf * 2.0 * kPiD * kPiD;  // integral of pdf d(theta) d(phi)
        total_without_sin += mass_without_sin[at];
      }
    }
    for (double& m : mass_without_sin) m /= total_without_sin;

    std::vector<double> observed(size_t(phi_bins) * cos_bins, 0.0);
    Rng rng(23, 0);
    for (int k = 0; k < samples; ++k) {
      float pdf = 0.0f;
      const Vec3 w = env.sample_direction(rng.uniform2(), &pdf);
      observed[size_t(direction_cell(w, phi_bins, cos_bins))] += 1.0;
    }
    auto expected = cell_probabilities(mass, image.width, image.height, phi_bins, cos_bins);
    for (double& e : expected) e *= samples;
    const auto good = test::chi_square_test(observed, expected);
    EXPECT_GT(good.p_value, 1e-3) << "chi2 " << good.statistic << " dof "
                                  << good.degrees_of_freedom;

    auto wrong = cell_probabilities(mass_without_sin, image.width, image.height, phi_bins,
                                    cos_bins);
    for (double& e : wrong) e *= samples;
    const auto bad = test::chi_square_test(observed, wrong);
    EXPECT_LT(bad.p_value, 1e-9) << "the test cannot tell a missing sin(theta): chi2 "
                                 << bad.statistic;
  }
}

// T-ENV-4: equal radiance in a polar and an equatorial band of four rows each: the
// probabilities follow solid angle, not texel count, and the pdfs agree.
TEST(EnvironmentMap, BandsOfEqualRadianceAreSampledBySolidAngle) {
  Image map(64, 32);
  for (int y : {0, 1, 2, 3, 14, 15, 16, 17}) {
    for (int x = 0; x < 64; ++x) map.at(x, y) = Rgb(2.0f);
  }
  const EnvironmentMap env(map, 1.0f, Mat3(1.0f));
  const double polar = 1.0 - std::cos(4.0 * kPiD / 32.0);
  const double equatorial = std::cos(14.0 * kPiD / 32.0) - std::cos(18.0 * kPiD / 32.0);
  const double expected = polar / (polar + equatorial);

  const int samples = 200000;
  int in_polar = 0;
  Rng rng(24, 0);
  for (int k = 0; k < samples; ++k) {
    float pdf = 0.0f;
    const Vec3 w = env.sample_direction(rng.uniform2(), &pdf);
    in_polar += w.y > std::cos(4.0 * kPiD / 32.0) - 1e-6;
  }
  const double fraction = double(in_polar) / samples;
  const double sigma = std::sqrt(expected * (1.0 - expected) / samples);
  EXPECT_NEAR(fraction, expected, 4.0 * sigma);
  EXPECT_LT(fraction, 0.3);  // texel counting would give 0.5

  // Equal radiance => equal solid-angle density = 1 / (total solid angle) at texel centres.
  const double uniform = 1.0 / (2.0 * kPiD * (polar + equatorial));
  for (int y : {0, 3, 14, 17}) {
    const float pdf = env.pdf_direction(latlong_to_direction(Vec2(0.3f, (y + 0.5f) / 32.0f)));
    EXPECT_NEAR(pdf, uniform, 2e-3 * uniform) << "row " << y;
  }
}

// Rotation: radiance and pdf follow to_world; samples rotate with the map.
TEST(EnvironmentMap, RotationMovesRadianceAndPdfTogether) {
  const Mat3 rotation(glm::rotate(Mat4(1.0f), glm::radians(37.0f),
                                  glm::normalize(Vec3(1.0f, 2.0f, 3.0f))));
  const Image texels = smooth_map();
  const EnvironmentMap plain(texels, 1.5f, Mat3(1.0f));
  const EnvironmentMap rotated(texels, 1.5f, rotation);
  Rng rng(25, 0);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 64; ++x) {
      // Jittered within the inner 60% of the texel, away from lookup edges.
      const Vec2 uv((x + 0.2f + 0.6f * rng.uniform()) / 64.0f,
                    (y + 0.2f + 0.6f * rng.uniform()) / 32.0f);
      const Vec3 w = latlong_to_direction(uv);
      ASSERT_EQ(rotated.radiance(rotation * w), plain.radiance(w));
      ASSERT_EQ(plain.radiance(w), 1.5f * texels.at(x, y));
      const float pdf = plain.pdf_direction(w);
      ASSERT_NEAR(rotated.pdf_direction(rotation * w), pdf, 1e-4f * pdf + 1e-12f);
    }
  }
  int agree = 0;
  const int samples = 20000;
  for (int k = 0; k < samples; ++k) {
    const Vec2 u = rng.uniform2();
    float pdf_plain = 0.0f, pdf_rotated = 0.0f;
    const Vec3 w_plain = plain.sample_direction(u, &pdf_plain);
    const Vec3 w_rotated = rotated.sample_direction(u, &pdf_rotated);
    ASSERT_LT(glm::length(w_rotated - rotation * w_plain), 1e-5f);
    ASSERT_NEAR(pdf_rotated, rotated.pdf_direction(w_rotated), 1e-6f * pdf_rotated);
    // Equal unless the rotated round trip crosses a texel edge (float round-off).
    agree += std::abs(pdf_rotated - pdf_plain) <= 1e-3f * pdf_plain;
  }
  EXPECT_GE(agree, samples - samples / 1000);
  EXPECT_NEAR(luminance(rotated.power()), luminance(plain.power()),
              1e-6f * luminance(plain.power()));
}

// T-ENV-5: a constant sky gives irradiance pi L at an up-facing point through direct-light
// sampling, both as a map and as ConstantEnvironment; power is pi R^2 4 pi L.
TEST(EnvironmentMap, ConstantSkyIrradianceIsPiL) {
  const Rgb sky(0.5f, 1.0f, 2.0f);
  const EnvironmentMap map(Image(32, 16, sky), 1.0f, Mat3(1.0f));
  const ConstantEnvironment constant(sky);
  const EnvironmentLight* lights[] = {&map, &constant};
  for (const EnvironmentLight* env : lights) {
    Rng rng(26, 0);
    const int samples = 1000000;
    DVec3 sum(0.0);
    for (int k = 0; k < samples; ++k) {
      const auto s = env->sample_direct(Vec3(1.0f, 2.0f, 3.0f), rng.uniform2());
      ASSERT_TRUE(s.has_value());
      ASSERT_EQ(s->distance, kInfinity);
      ASSERT_NEAR(env->pdf_direct(Vec3(0.0f), s->position, s->normal, s->wi), s->pdf,
                  1e-6f * s->pdf);
      sum += DVec3(s->radiance) * double(std::max(0.0f, s->wi.y)) / double(s->pdf);
    }
    const DVec3 mean = sum / double(samples);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], kPiD * sky[c], 0.01 * kPiD * sky[c]);
  }
  EnvironmentMap scaled(Image(32, 16, sky), 1.0f, Mat3(1.0f));
  scaled.set_scene_bounds(Vec3(0.0f), 3.0f);
  ConstantEnvironment constant_scaled(sky);
  constant_scaled.set_scene_bounds(Vec3(0.0f), 3.0f);
  const double expected_power = kPiD * 9.0 * 4.0 * kPiD * luminance(sky);
  EXPECT_NEAR(luminance(scaled.power()), expected_power, 1e-4 * expected_power);
  EXPECT_NEAR(luminance(constant_scaled.power()), expected_power, 1e-4 * expected_power);
}

// §6.4: sun + sky irradiance at an up-facing point. Environment importance sampling and
// cosine sampling agree with the exact irradiance of the (nearest-texel) map, and the
// environment sampler's variance is at least 10x lower (about three orders in practice).
TEST(EnvironmentMap, SunSkyImportanceSamplingBeatsCosineSampling) {
  const Image image = sun_sky_map();
  const EnvironmentMap env(image, 1.0f, Mat3(1.0f));
  // Exact: rows 0..31 are the upper hemisphere; over a texel, integral of cos theta d omega
  // is delta_phi (sin^2 theta1 - sin^2 theta0) / 2.
  double exact = 0.0;
  for (int y = 0; y < image.height / 2; ++y) {
    const double s0 = std::sin(kPiD * y / image.height), s1 = std::sin(kPiD * (y + 1) / image.height);
    for (int x = 0; x < image.width; ++x) {
      exact += luminance(image.at(x, y)) * (2.0 * kPiD / image.width) * (s1 * s1 - s0 * s0) / 2.0;
    }
  }
  const int samples = 200000;
  auto estimate = [&](bool importance, double* mean, double* variance) {
    Rng rng(importance ? 27 : 28, 0);
    double sum = 0.0, sum_sq = 0.0;
    for (int k = 0; k < samples; ++k) {
      double value = 0.0;
      if (importance) {
        const auto s = env.sample_direct(Vec3(0.0f), rng.uniform2());
        if (s) value = luminance(s->radiance) * std::max(0.0f, s->wi.y) / s->pdf;
      } else {
        const Vec3 local = square_to_cosine_hemisphere(rng.uniform2());
        const Vec3 w(local.x, local.z, local.y);  // z-up hemisphere -> y-up world
        value = luminance(env.radiance(w)) * kPi;  // cos / (cos / pi)
      }
      sum += value;
      sum_sq += value * value;
    }
    *mean = sum / samples;
    *variance = std::max(0.0, sum_sq / samples - *mean * *mean);
  };
  double mean_env, var_env, mean_cos, var_cos;
  estimate(true, &mean_env, &var_env);
  estimate(false, &mean_cos, &var_cos);
  const double sigma_env = std::sqrt(var_env / samples), sigma_cos = std::sqrt(var_cos / samples);
  EXPECT_NEAR(mean_env, exact, 4.0 * sigma_env + 1e-6 * exact);
  EXPECT_NEAR(mean_cos, exact, 4.0 * sigma_cos + 1e-6 * exact);
  EXPECT_NEAR(mean_env, mean_cos, 4.0 * std::hypot(sigma_env, sigma_cos));
  EXPECT_GT(var_cos, 10.0 * var_env) << "cosine " << var_cos << " env " << var_env;
  RecordProperty("variance_ratio_cosine_over_env", std::to_string(var_cos / var_env));
}

// Emission from the sky: rays start on the disk facing the sampled direction, run into the
// scene, and the pdfs agree with pdf_emission().
TEST(EnvironmentMap, EmissionRaysCoverTheSceneDisk) {
  EnvironmentMap env(sun_sky_map(), 1.0f, Mat3(1.0f));
  const Vec3 center(1.0f, -2.0f, 0.5f);
  const float radius = 4.0f;
  env.set_scene_bounds(center, radius);
  Rng rng(29, 0);
  double max_offset = 0.0;
  for (int k = 0; k < 50000; ++k) {
    const auto e = env.sample_emission(rng.uniform2(), rng.uniform2());
    ASSERT_TRUE(e.has_value());
    const Vec3 d = e->ray.direction;
    ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
    const Vec3 rel = e->ray.origin - center;
    // The origin lies on the disk of radius R, R away from the centre towards the sky.
    ASSERT_NEAR(glm::dot(rel, -d), radius, 1e-3f * radius);
    const Vec3 lateral = rel - glm::dot(rel, d) * d;
    ASSERT_LE(glm::length(lateral), radius * (1.0f + 1e-5f));
    max_offset = std::max(max_offset, double(glm::length(lateral)));
    float pdf_position = 0.0f, pdf_direction = 0.0f;
    env.pdf_emission(e->ray.origin, e->normal, d, &pdf_position, &pdf_direction);
    ASSERT_NEAR(pdf_position, 1.0f / (kPi * radius * radius), 1e-7f);
    ASSERT_NEAR(pdf_position, e->pdf_position, 1e-7f);
    ASSERT_NEAR(pdf_direction, e->pdf_direction, 1e-5f * e->pdf_direction);
    ASSERT_EQ(e->radiance, env.radiance(-d));
  }
  EXPECT_GT(max_offset, 0.95 * radius);  // the whole disk is used
}
