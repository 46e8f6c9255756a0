// Environment maps (the checks T-ENV-1..5 and their variance figures):
// Mitsuba 0.6's bilinear radiance lookup, and importance sampling whose pdf is exactly the
// density it samples. Maps are synthesised here; the test keeps its own lookup and texel
// table so that radiance and pdf are checked against the formulas, not only against
// themselves.
#include "emlt/scene/environment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/core/warp.h"
#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/direct_integrator.h"
#include "emlt/integrators/path_tracer.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

constexpr double kPiD = 3.14159265358979323846;
using DVec2 = glm::dvec2;

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

// The test's own bilinear lookup, written from Mitsuba 0.6's convention (envmap.cpp's
// evalBilinear(0, uv), mipmap.h) rather than from the renderer's code: texel (i, j) is
// centred at ((i + 0.5) / W, (j + 0.5) / H), columns repeat (phi is periodic) and rows
// clamp (the poles).
template <class Texel>  // Texel(int x, int y) -> double
double bilinear(int width, int height, double u, double v, const Texel& texel) {
  const double x = u * width - 0.5, y = v * height - 0.5;
  const double x_floor = std::floor(x), y_floor = std::floor(y);
  const double fx = x - x_floor, fy = y - y_floor;
  const int x0 = int(x_floor), y0 = int(y_floor);
  const auto column = [width](int i) { return ((i % width) + width) % width; };
  const auto row = [height](int j) { return std::clamp(j, 0, height - 1); };
  return (1 - fx) * (1 - fy) * texel(column(x0), row(y0)) +
         fx * (1 - fy) * texel(column(x0 + 1), row(y0)) +
         (1 - fx) * fy * texel(column(x0), row(y0 + 1)) +
         fx * fy * texel(column(x0 + 1), row(y0 + 1));
}

// Lat-long coordinates of a unit direction, in double: u = atan2(x, -z) / 2 pi in [0,1),
// v = acos(y) / pi.
DVec2 latlong(const Vec3& w) {
  double u = std::atan2(double(w.x), -double(w.z)) / (2.0 * kPiD);
  if (u < 0.0) u += 1.0;
  return {u, std::acos(std::clamp(double(w.y), -1.0, 1.0)) / kPiD};
}

// Radiance of the map (identity rotation) by the reference lookup.
DVec3 reference_radiance(const Image& map, double scale, const Vec3& w) {
  const DVec2 uv = latlong(w);
  DVec3 value(0.0);
  for (int c = 0; c < 3; ++c) {
    value[c] = scale * bilinear(map.width, map.height, uv.x, uv.y,
                                [&](int x, int y) { return double(map.at(x, y)[c]); });
  }
  return value;
}

// The test's own sampling model: texel probabilities P_ij proportional to luminance x
// sin(theta_centre); the sampler's (u, v) density is the bilinear interpolation of P per
// unit pixel area (a tent around each texel centre), and the solid-angle pdf divides that
// by the lat-long Jacobian 2 pi^2 sin(theta). `piecewise_constant` is the old sampler
// (uniform within each texel), kept to show that the tests can tell the two apart.
struct ReferenceTable {
  int width, height;
  std::vector<double> probability;
  bool piecewise_constant = false;

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
  double texel(int x, int y) const { return probability[size_t(y) * width + x]; }
  double density_uv(double u, double v) const {
    if (piecewise_constant) {
      return texel(std::min(int(u * width), width - 1), std::min(int(v * height), height - 1)) *
             width * height;
    }
    return bilinear(width, height, u, v, [this](int x, int y) { return texel(x, y); }) * width *
           height;
  }
  double pdf(const Vec3& w) const {
    const DVec2 uv = latlong(w);
    const double sin_theta = std::sqrt(double(w.x) * w.x + double(w.z) * w.z);
    return density_uv(uv.x, uv.y) / (2.0 * kPiD * kPiD * sin_theta);
  }
  // The largest solid-angle pdf at a texel centre (a scale for absolute tolerances).
  double peak_pdf() const {
    double peak = 0.0;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        peak = std::max(peak, texel(x, y) * width * height /
                                  (2.0 * kPiD * kPiD * std::sin(kPiD * (y + 0.5) / height)));
      }
    }
    return peak;
  }
  // Probability of the (u, v) rectangle [u0,u1] x [v0,v1], exactly: cut at texel edges
  // and centres, each piece lies in one bilinear patch (and one texel), where the mean of
  // the density is its value at the piece's centre.
  double mass(double u0, double u1, double v0, double v1) const {
    const auto cuts = [](double a, double b, int n) {
      std::vector<double> c{a};
      for (int k = 1; k < 2 * n; ++k) {
        const double t = k / (2.0 * n);
        if (t > a && t < b) c.push_back(t);
      }
      c.push_back(b);
      return c;
    };
    const std::vector<double> us = cuts(u0, u1, width), vs = cuts(v0, v1, height);
    double sum = 0.0;
    for (size_t j = 0; j + 1 < vs.size(); ++j) {
      for (size_t i = 0; i + 1 < us.size(); ++i) {
        sum += (us[i + 1] - us[i]) * (vs[j + 1] - vs[j]) *
               density_uv(0.5 * (us[i] + us[i + 1]), 0.5 * (vs[j] + vs[j + 1]));
      }
    }
    return sum;
  }
};

// Probability of each (phi, cos theta) cell under the table: cells are rectangles in
// (u, v) once cos theta is mapped to v = acos(cos theta) / pi.
std::vector<double> cell_probabilities(const ReferenceTable& table, int phi_bins, int cos_bins) {
  std::vector<double> cells(size_t(phi_bins) * cos_bins, 0.0);
  for (int j = 0; j < cos_bins; ++j) {
    // cos bin j covers cos theta in [1 - 2(j+1)/n, 1 - 2j/n]: v from acos(top) to acos(bottom).
    const double v0 = std::acos(1.0 - 2.0 * j / cos_bins) / kPiD;
    const double v1 = std::acos(std::max(-1.0, 1.0 - 2.0 * (j + 1) / cos_bins)) / kPiD;
    for (int i = 0; i < phi_bins; ++i) {
      cells[size_t(j) * phi_bins + i] =
          table.mass(double(i) / phi_bins, (i + 1.0) / phi_bins, v0, v1);
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

// Irradiance (per channel) at an up-facing point from the map (identity rotation) by the
// reference bilinear lookup. Over a full turn in u the repeat-in-u interpolation averages
// to the row means, interpolated linearly in v (clamped at the poles); so
// E = 2 pi^2 * integral over v in [0, 1/2] of m(v) sin(pi v) cos(pi v), which Simpson's
// rule integrates to ~1e-12 between row centres, where m is linear.
DVec3 up_irradiance_bilinear(const Image& map, double scale) {
  DVec3 irradiance(0.0);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> row_mean(size_t(map.height), 0.0);
    for (int y = 0; y < map.height; ++y) {
      for (int x = 0; x < map.width; ++x) row_mean[size_t(y)] += map.at(x, y)[c];
      row_mean[size_t(y)] *= scale / map.width;
    }
    const auto m = [&](double v) {
      return bilinear(1, map.height, 0.5, v, [&](int, int y) { return row_mean[size_t(y)]; });
    };
    const auto f = [&](double v) {
      return m(v) * 2.0 * kPiD * kPiD * std::sin(kPiD * v) * std::cos(kPiD * v);
    };
    std::vector<double> cuts{0.0};
    for (int y = 0; y < map.height; ++y) {
      if ((y + 0.5) / map.height < 0.5) cuts.push_back((y + 0.5) / map.height);
    }
    cuts.push_back(0.5);
    for (size_t k = 0; k + 1 < cuts.size(); ++k) {
      const int n = 256;  // even
      const double a = cuts[k], h = (cuts[k + 1] - a) / n;
      double sum = f(a) + f(cuts[k + 1]);
      for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
      irradiance[c] += sum * h / 3.0;
    }
  }
  return irradiance;
}

// The same for the nearest-texel map, exactly: over texel rows above the horizon (H even),
// the integral of cos theta d omega over a row is pi (sin^2 theta1 - sin^2 theta0).
DVec3 up_irradiance_nearest(const Image& map, double scale) {
  DVec3 irradiance(0.0);
  for (int y = 0; y < map.height / 2; ++y) {
    const double s0 = std::sin(kPiD * y / map.height), s1 = std::sin(kPiD * (y + 1) / map.height);
    for (int x = 0; x < map.width; ++x) {
      irradiance += scale * DVec3(map.at(x, y)) * (2.0 * kPiD / map.width) * (s1 * s1 - s0 * s0) / 2.0;
    }
  }
  return irradiance;
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

// T-ENV-2: every sample's pdf equals pdf_direction() and the independent formula (the
// bilinear interpolation of the texel table); samples never land where the sky is black;
// poles and the phi seam give finite values. Absolute slack: float u, v carry ~1e-6 texel
// of error, which matters where a bright texel's tent is about to vanish.
TEST(EnvironmentMap, SampledPdfEqualsEvaluatedPdf) {
  for (const Image& image : {smooth_map(), sun_sky_map()}) {
    const EnvironmentMap env(image, 1.0f, Mat3(1.0f));
    const ReferenceTable table(image, 1.0f);
    const double slack = 1e-5 * table.peak_pdf();
    Rng rng(22, 0);
    for (int k = 0; k < 100000; ++k) {
      float pdf = 0.0f;
      const Vec3 w = env.sample_direction(rng.uniform2(), &pdf);
      ASSERT_NEAR(glm::length(w), 1.0f, 1e-5f);
      ASSERT_GT(pdf, 0.0f);
      ASSERT_EQ(pdf, env.pdf_direction(w));
      ASSERT_NEAR(pdf, table.pdf(w), 1e-3 * table.pdf(w) + slack) << "sample " << k;
      ASSERT_GT(luminance(env.radiance(w)), 0.0f);  // never where the sky is black
    }
    // Near the poles, across the phi = 0 seam, on texel edges.
    for (float theta : {1e-3f, 0.02f, 1.0f, kPi - 0.02f, kPi - 1e-3f}) {
      for (float phi : {0.0f, 1e-6f, kTwoPi - 1e-6f, kTwoPi * 10.0f / 64.0f, 2.0f}) {
        const Vec3 w(std::sin(theta) * std::sin(phi), std::cos(theta),
                     -std::sin(theta) * std::cos(phi));
        const float pdf = env.pdf_direction(w);
        ASSERT_TRUE(std::isfinite(pdf));
        EXPECT_NEAR(pdf, table.pdf(w), 2e-3 * table.pdf(w) + slack) << theta << " " << phi;
      }
    }
    EXPECT_EQ(env.pdf_direction(Vec3(0.0f, 1.0f, 0.0f)), 0.0f);
    EXPECT_EQ(env.pdf_direction(Vec3(0.0f, -1.0f, 0.0f)), 0.0f);
  }
  // Between the centres of two black texels (columns 38, 39 of the smooth map) the lookup
  // reaches only black texels: zero radiance and zero density. Half a texel further it
  // reaches lit column 35 or 42, and both become positive.
  const EnvironmentMap smooth(smooth_map(), 1.0f, Mat3(1.0f));
  const Vec3 black = latlong_to_direction(Vec2(39.0f / 64.0f, 0.5f));
  EXPECT_EQ(smooth.pdf_direction(black), 0.0f);
  EXPECT_EQ(smooth.radiance(black), Rgb(0.0f));
  for (float x : {36.2f, 41.8f}) {
    const Vec3 lit = latlong_to_direction(Vec2(x / 64.0f, 0.5f));
    EXPECT_GT(luminance(smooth.radiance(lit)), 0.0f) << x;
    EXPECT_GT(smooth.pdf_direction(lit), 0.0f) << x;
  }
}

// T-ENV-3: chi-square of 10^6 sampled directions over (phi, cos theta) cells against the
// reference density integrated over each cell. The same histogram must reject the
// distribution whose measure drops sin(theta) (texel weights by luminance alone), and the
// old piecewise-constant sampler (uniform within each texel, no tent).
TEST(EnvironmentMap, ChiSquareOverSolidAngleCells) {
  const int phi_bins = 64, cos_bins = 32, samples = 1000000;
  for (const Image& image : {smooth_map(), sun_sky_map()}) {
    const EnvironmentMap env(image, 1.0f, Mat3(1.0f));
    std::vector<double> observed(size_t(phi_bins) * cos_bins, 0.0);
    Rng rng(23, 0);
    for (int k = 0; k < samples; ++k) {
      float pdf = 0.0f;
      const Vec3 w = env.sample_direction(rng.uniform2(), &pdf);
      observed[size_t(direction_cell(w, phi_bins, cos_bins))] += 1.0;
    }
    const auto expected_counts = [&](const ReferenceTable& table) {
      auto expected = cell_probabilities(table, phi_bins, cos_bins);
      for (double& e : expected) e *= samples;
      return expected;
    };
    const ReferenceTable table(image, 1.0f);
    const auto good = test::chi_square_test(observed, expected_counts(table));
    EXPECT_GT(good.p_value, 1e-3) << "chi2 " << good.statistic << " dof "
                                  << good.degrees_of_freedom;

    const auto no_sin = test::chi_square_test(observed, expected_counts(ReferenceTable(image, 1.0f, false)));
    EXPECT_LT(no_sin.p_value, 1e-9) << "the test cannot tell a missing sin(theta): chi2 "
                                    << no_sin.statistic;
    ReferenceTable uniform_in_texel = table;
    uniform_in_texel.piecewise_constant = true;
    const auto flat = test::chi_square_test(observed, expected_counts(uniform_in_texel));
    EXPECT_LT(flat.p_value, 1e-9) << "the test cannot tell a missing tent: chi2 "
                                  << flat.statistic;
  }
}

// T-ENV-4: equal radiance in a polar and an equatorial band of four rows each: the
// probabilities follow solid angle, not texel count, and the pdfs agree. The sampled
// polar fraction is the reference's: the tent spills 1/8 of the band's last row past its
// edge (that spill alone is 10 sigma here, so a sampler without it fails).
TEST(EnvironmentMap, BandsOfEqualRadianceAreSampledBySolidAngle) {
  Image map(64, 32);
  for (int y : {0, 1, 2, 3, 14, 15, 16, 17}) {
    for (int x = 0; x < 64; ++x) map.at(x, y) = Rgb(2.0f);
  }
  const EnvironmentMap env(map, 1.0f, Mat3(1.0f));
  const double polar = 1.0 - std::cos(4.0 * kPiD / 32.0);
  const double equatorial = std::cos(14.0 * kPiD / 32.0) - std::cos(18.0 * kPiD / 32.0);
  const double expected = ReferenceTable(map, 1.0f).mass(0.0, 1.0, 0.0, 4.0 / 32.0);

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
  const double peak_pdf = ReferenceTable(texels, 1.5f).peak_pdf();
  Rng rng(25, 0);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 64; ++x) {
      // Jittered over the texel. The lookup is continuous, so the rotation's float
      // round-off (~1e-6 texel) moves it by at most ~1e-6 x the texel contrast (~150).
      // Kept 0.01 in v off the poles, where that round-off is a large part of sin(theta)
      // and so of the pdf's Jacobian.
      const Vec2 uv((x + rng.uniform()) / 64.0f,
                    std::clamp((y + rng.uniform()) / 32.0f, 0.01f, 0.99f));
      const Vec3 w = latlong_to_direction(uv);
      const Rgb value = plain.radiance(w), turned = rotated.radiance(rotation * w);
      const DVec3 reference = reference_radiance(texels, 1.5, w);
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(turned[c], value[c], 1e-3f) << x << " " << y;
        ASSERT_NEAR(value[c], reference[c], 1e-4 * reference[c] + 1e-4) << x << " " << y;
      }
      const float pdf = plain.pdf_direction(w);
      ASSERT_NEAR(rotated.pdf_direction(rotation * w), pdf, 1e-4 * pdf + 1e-5 * peak_pdf) << x << " " << y;
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
    // Equal up to the rotation's round-off, which matters only where the density nearly
    // vanishes (the last 1e-5 of a tent next to a black texel).
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
// cosine sampling agree with the exact irradiance of the (bilinearly interpolated) map,
// and the environment sampler's variance is at least 10x lower (about three orders in
// practice).
TEST(EnvironmentMap, SunSkyImportanceSamplingBeatsCosineSampling) {
  const Image image = sun_sky_map();
  const EnvironmentMap env(image, 1.0f, Mat3(1.0f));
  const double exact = double(luminance(Rgb(up_irradiance_bilinear(image, 1.0))));
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

// Mitsuba 0.6's lookup, by hand on a 4 x 2 map (texel a(x, y) x (1, 2, 0.5), scale 2):
// texel centres give the texel, half-way between centres the mean; u repeats across the
// seam at phi = 0 and v clamps within half a texel of the poles.
TEST(EnvironmentMap, BilinearLookupMatchesHandComputedValues) {
  const float a[2][4] = {{1, 2, 3, 4}, {10, 20, 30, 40}};
  Image map(4, 2);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) map.at(x, y) = a[y][x] * Rgb(1.0f, 2.0f, 0.5f);
  }
  const EnvironmentMap env(map, 2.0f, Mat3(1.0f));
  struct Probe {
    float u, v, expected;
    const char* what;
  };
  const Probe probes[] = {
      {1.5f / 4, 0.25f, 2.0f, "texel centre"},
      {2.5f / 4, 0.75f, 30.0f, "texel centre, lower row"},
      {2.0f / 4, 0.25f, 2.5f, "between two centres in u"},
      {1.75f / 4, 0.5f, 12.375f, "between four centres: (2.25 + 22.5) / 2"},
      {0.0f, 0.25f, 2.5f, "on the seam: columns 3 and 0"},
      {0.05f, 0.25f, 1.9f, "just past the seam: 0.3 x 4 + 0.7 x 1"},
      {0.95f, 0.25f, 3.1f, "just before the seam: 0.7 x 4 + 0.3 x 1"},
      {0.05f, 0.97f, 19.0f, "seam near the lower pole: 0.3 x 40 + 0.7 x 10"},
      {1.5f / 4, 0.1f, 2.0f, "near the upper pole: row 0 only (clamp)"},
      {2.0f / 4, 0.01f, 2.5f, "next to the upper pole, between columns"},
      {2.5f / 4, 0.9f, 30.0f, "near the lower pole: row 1 only (clamp)"},
  };
  for (const Probe& probe : probes) {
    const Rgb value = env.radiance(latlong_to_direction(Vec2(probe.u, probe.v)));
    const Rgb expected = 2.0f * probe.expected * Rgb(1.0f, 2.0f, 0.5f);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(value[c], expected[c], 1e-4f * expected[c]) << probe.what << ", channel " << c;
    }
  }
}

// The density must be positive wherever the interpolated radiance is (else light-only
// strategies such as BDPT's light tracing miss that light), and zero where it is black
// (no wasted samples). Probed on a dense jittered grid over a mostly black map with an
// isolated texel, a black texel ringed by lit ones, and a lit texel at the seam by a pole.
TEST(EnvironmentMap, PdfIsPositiveExactlyWhereRadianceIs) {
  Image map(16, 8);
  map.at(3, 2) = Rgb(5.0f, 0.0f, 0.0f);
  for (int y = 4; y <= 6; ++y) {
    for (int x = 9; x <= 11; ++x) map.at(x, y) = Rgb(1.0f);
  }
  map.at(10, 5) = Rgb(0.0f);
  map.at(15, 7) = Rgb(0.0f, 0.0f, 3.0f);
  const EnvironmentMap env(map, 1.0f, Mat3(1.0f));
  Rng rng(30, 0);
  int lit = 0, lit_inside_black_texel = 0, mismatches = 0;
  for (int j = 0; j < 256; ++j) {
    for (int i = 0; i < 512; ++i) {
      const Vec2 uv((i + rng.uniform()) / 512.0f, (j + rng.uniform()) / 256.0f);
      const Vec3 w = latlong_to_direction(uv);
      if (!(std::sqrt(w.x * w.x + w.z * w.z) > 0.0f)) continue;  // exactly a pole
      const bool bright = luminance(env.radiance(w)) > 0.0f;
      const bool sampled = env.pdf_direction(w) > 0.0f;
      mismatches += bright != sampled;
      lit += bright;
      lit_inside_black_texel += bright && int(uv.x * 16) == 10 && int(uv.y * 8) == 5;
      if (bright != sampled && mismatches <= 5) {
        ADD_FAILURE() << "u " << uv.x << " v " << uv.y << ": radiance "
                      << luminance(env.radiance(w)) << ", pdf " << env.pdf_direction(w);
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
  // The probes do reach the light the interpolation carries into black texels.
  EXPECT_GT(lit_inside_black_texel, 1000);
  EXPECT_GT(lit, 10000);
  for (int k = 0; k < 100000; ++k) {
    float pdf = 0.0f;
    const Vec3 w = env.sample_direction(rng.uniform2(), &pdf);
    ASSERT_GT(pdf, 0.0f);
    ASSERT_GT(luminance(env.radiance(w)), 0.0f);
  }
}

namespace {

// An 8 x 4 sky with strong texel contrast, where the bilinear and the nearest-texel
// lookups give irradiances far apart: a lit top row with a black texel, a dim second row
// with a sun texel, and a bright row below the horizon whose interpolation reaches above it.
Image contrast_sky() {
  Image map(8, 4);
  for (int x = 0; x < 8; ++x) {
    map.at(x, 0) = Rgb(1.0f, 0.8f, 0.6f) * (1.0f + 0.5f * std::sin(float(x)));
    map.at(x, 1) = Rgb(0.2f, 0.25f, 0.3f);
    map.at(x, 2) = Rgb(8.0f, 6.0f, 4.0f);
    map.at(x, 3) = Rgb(0.0f);
  }
  map.at(6, 0) = Rgb(0.0f);
  map.at(3, 1) = Rgb(30.0f, 27.0f, 21.0f);
  return map;
}

}  // namespace

// Environment sampling alone (no MIS partner to cover for it) estimates the irradiance
// of the interpolated map at an up-facing point: a sampler whose support or pdf differed
// from the lookup's would be biased here.
TEST(EnvironmentMap, LightSamplingAloneGivesTheInterpolatedIrradiance) {
  const Image map = contrast_sky();
  const float scale = 1.5f;
  const EnvironmentMap env(map, scale, Mat3(1.0f));
  const DVec3 exact = up_irradiance_bilinear(map, scale);
  const DVec3 nearest = up_irradiance_nearest(map, scale);
  Rng rng(31, 0);
  const int samples = 4000000;
  DVec3 sum(0.0), sum_sq(0.0);
  for (int k = 0; k < samples; ++k) {
    const auto s = env.sample_direct(Vec3(0.0f), rng.uniform2());
    if (!s) continue;
    const DVec3 value = DVec3(s->radiance) * double(std::max(0.0f, s->wi.y)) / double(s->pdf);
    sum += value;
    sum_sq += value * value;
  }
  for (int c = 0; c < 3; ++c) {
    const double mean = sum[c] / samples;
    const double sigma = std::sqrt((sum_sq[c] / samples - mean * mean) / samples);
    EXPECT_NEAR(mean, exact[c], 4.0 * sigma) << "channel " << c;
    EXPECT_GT(std::abs(nearest[c] - exact[c]), 15.0 * sigma) << "the map does not discriminate";
  }
}

// The same sky over a large diffuse floor seen from above: every integrator must give the
// floor radiance albedo / pi x (irradiance of the interpolated map), path tracing and
// direct lighting (MIS of BSDF and environment sampling) as well as BDPT (light tracing
// from the sky as well).
TEST(EnvironmentMap, IntegratorsAgreeWithTheInterpolatedIrradiance) {
  const Image map = contrast_sky();
  const float scale = 1.5f;
  const Rgb albedo(0.25f, 0.5f, 0.75f);
  SceneDescription d;
  d.source = "env-floor";
  const int m = test::add_material(d, make_lambertian(albedo));
  test::add_quad(d, Vec3(-100, 0, -100), Vec3(-100, 0, 100), Vec3(100, 0, 100),
                 Vec3(100, 0, -100), m);
  d.environment.kind = EnvironmentDesc::Kind::Map;
  d.environment.map = map;
  d.environment.scale = scale;
  d.camera = test::camera_at(Vec3(0, 2, 0), Vec3(0.1f, 0, 0.1f), 16, Vec3(0, 0, 1));
  const auto scene = Scene::build(std::move(d));
  const DVec3 irradiance = up_irradiance_bilinear(map, scale);

  const PathTracer pt;
  const DirectIntegrator direct;
  const BidirectionalPathTracer bdpt;
  for (const Integrator* integrator : std::initializer_list<const Integrator*>{&pt, &direct, &bdpt}) {
    RenderSettings s;
    s.spp = 64;
    s.progress = false;
    ProgressReporter progress(false);
    const Image image = integrator->render(*scene, s, progress).image;
    for (int c = 0; c < 3; ++c) {
      double sum = 0.0, sum_sq = 0.0;
      for (const Rgb& p : image.pixels) {
        sum += p[c];
        sum_sq += double(p[c]) * p[c];
      }
      const double n = double(image.pixels.size()), mean = sum / n;
      const double se = std::sqrt(std::max(sum_sq / n - mean * mean, 0.0) / n);
      const double expected = albedo[c] / kPiD * irradiance[c];
      EXPECT_NEAR(mean, expected, 5.0 * se + 0.002 * expected)
          << integrator->name() << ", channel " << c;
    }
  }
}
