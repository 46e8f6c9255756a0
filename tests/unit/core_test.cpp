#include <gtest/gtest.h>

#include "emlt/core/distribution.h"
#include "emlt/core/frame.h"
#include "emlt/core/rng.h"
#include "emlt/core/warp.h"
#include "support/test_support.h"

using namespace emlt;

TEST(Rng, StreamsAreReproducibleAndDistinct) {
  Rng a = Rng::for_item(7, 3), b = Rng::for_item(7, 3), c = Rng::for_item(7, 4);
  int same_as_c = 0;
  for (int i = 0; i < 1000; ++i) {
    const uint32_t x = a.next_u32();
    EXPECT_EQ(x, b.next_u32());
    same_as_c += (x == c.next_u32());
  }
  EXPECT_LT(same_as_c, 3);
}

TEST(Rng, UniformIsInUnitIntervalWithCorrectMean) {
  Rng rng(1, 2);
  double sum = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const float u = rng.uniform();
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    sum += u;
  }
  EXPECT_NEAR(sum / n, 0.5, 4.0 * std::sqrt(1.0 / 12.0 / n));
}

TEST(Frame, IsOrthonormalForManyNormals) {
  Rng rng(3, 0);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 n = square_to_uniform_sphere(rng.uniform2());
    const Frame f(n);
    EXPECT_NEAR(glm::dot(f.s, f.t), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(f.s, f.n), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(f.s), 1.0f, 1e-5f);
    const Vec3 w = square_to_uniform_sphere(rng.uniform2());
    const Vec3 back = f.to_world(f.to_local(w));
    EXPECT_NEAR(glm::length(back - w), 0.0f, 1e-5f);
  }
}

TEST(Distribution1D, DiscreteFrequenciesMatchWeights) {
  const Distribution1D d({1.0f, 0.0f, 3.0f, 4.0f});
  EXPECT_FLOAT_EQ(d.pmf(1), 0.0f);
  Rng rng(5, 0);
  std::vector<double> counts(4, 0.0), expected(4);
  const int n = 100000;
  for (int i = 0; i < n; ++i) counts[d.sample_discrete(rng.uniform())] += 1.0;
  for (int i = 0; i < 4; ++i) expected[i] = n * d.pmf(i);
  EXPECT_EQ(counts[1], 0.0);
  EXPECT_GT(test::chi_square_test(counts, expected).p_value, 1e-3);
}

TEST(Distribution1D, BucketIsTheFirstWhoseCdfExceedsU) {
  // Short tables are scanned, long ones searched (distribution.cpp): either way the bucket
  // is the first of non-zero mass whose cumulative weight exceeds u, zero-mass buckets at
  // the start, the middle and the end included, and u at every bucket's edges.
  for (const size_t size : {1, 2, 3, 15, 16, 17, 40}) {
    std::vector<float> weights(size);
    for (size_t i = 0; i < size; ++i)
      weights[i] = (i % 3 == 1 || i + 1 == size) ? 0.0f : float(i + 1);
    if (size <= 2) weights.assign(size, 1.0f);
    const Distribution1D d(weights);
    double total = 0.0;
    for (const float w : weights) total += w;
    std::vector<float> edges{0.0f, 0.5f, kOneMinusEpsilon};
    double sum = 0.0;
    for (const float w : weights) {
      sum += w;
      const float edge = float(sum / total);
      edges.insert(edges.end(), {edge, std::nextafter(edge, 0.0f), std::nextafter(edge, 1.0f)});
    }
    for (int k = 0; k < 1000; ++k) edges.push_back((float(k) + 0.5f) / 1000.0f);
    for (const float u : edges) {
      if (!(u >= 0.0f && u < 1.0f)) continue;
      size_t expected = size - 1;
      double cdf = 0.0;
      for (size_t i = 0; i < size; ++i) {
        cdf += weights[i] / total;
        if (cdf > double(u) && weights[i] > 0.0f) {
          expected = i;
          break;
        }
      }
      while (expected > 0 && weights[expected] == 0.0f) --expected;
      EXPECT_EQ(d.sample_discrete(u), expected) << "size " << size << ", u " << u;
    }
  }
}

TEST(Distribution2D, PdfMatchesSamplerAndIntegratesToOne) {
  std::vector<float> w(8 * 4);
  for (size_t i = 0; i < w.size(); ++i) w[i] = float((i * 7) % 5);
  const Distribution2D d(w, 8, 4);
  Rng rng(9, 0);
  for (int i = 0; i < 1000; ++i) {
    float pdf = 0.0f;
    const Vec2 p = d.sample(rng.uniform2(), &pdf);
    EXPECT_NEAR(pdf, d.pdf(p), 1e-4f * pdf);
    EXPECT_GT(pdf, 0.0f);
  }
  const double integral = test::integrate_2d(
      [&](double x, double y) { return d.pdf(Vec2(float(std::min(x, 0.999999)), float(std::min(y, 0.999999)))); },
      0, 1, 0, 1, 400);
  EXPECT_NEAR(integral, 1.0, 0.02);
}

TEST(Warp, CosineHemisphereHistogramMatchesPdf) {
  // Bin directions over (cos theta, phi) and compare with the integral of the pdf.
  const int nz = 10, nphi = 20, n = 200000;
  std::vector<double> counts(nz * nphi, 0.0), expected(nz * nphi, 0.0);
  Rng rng(11, 0);
  for (int i = 0; i < n; ++i) {
    const Vec3 w = square_to_cosine_hemisphere(rng.uniform2());
    float phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += kTwoPi;
    const int iz = std::min(int(w.z * nz), nz - 1), ip = std::min(int(phi / kTwoPi * nphi), nphi - 1);
    counts[iz * nphi + ip] += 1.0;
  }
  for (int iz = 0; iz < nz; ++iz)
    for (int ip = 0; ip < nphi; ++ip) {
      // integral of cos/pi over a (z, phi) cell = (z1^2 - z0^2)/2 * dphi / pi
      const double z0 = double(iz) / nz, z1 = double(iz + 1) / nz;
      expected[iz * nphi + ip] = n * (z1 * z1 - z0 * z0) / 2.0 * (2.0 * M_PI / nphi) / M_PI;
    }
  EXPECT_GT(test::chi_square_test(counts, expected).p_value, 1e-3);
}

TEST(Warp, ConcentricDiskIsTheExactMapToFloatRounding) {
  // The map's sine and cosine are polynomials over the reduced angle (warp.cpp): each point
  // must be the exact Shirley-Chiu image, computed here in double with libm, to within a
  // few float roundings, over a grid that reaches both branches and their seams.
  const int n = 512;
  double worst = 0.0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const Vec2 u(float(i) / n, float(j) / n);
      const double a = 2.0 * u.x - 1.0, b = 2.0 * u.y - 1.0;
      double r = 0.0, phi = 0.0;
      if (a != 0.0 || b != 0.0) {
        if (std::abs(a) > std::abs(b))
          r = a, phi = (M_PI / 4.0) * (b / a);
        else
          r = b, phi = M_PI / 2.0 - (M_PI / 4.0) * (a / b);
      }
      const Vec2 d = square_to_uniform_disk_concentric(u);
      worst =
          std::max({worst, std::abs(d.x - r * std::cos(phi)), std::abs(d.y - r * std::sin(phi))});
    }
  // A float's spacing near 1 is 1.2e-7; a Taylor series cut one term earlier errs by 3e-7.
  EXPECT_LT(worst, 2.5e-7);
}

TEST(Warp, UnitCirclePointIsCosAndSinOfTheTurn) {
  // cos and sin of 2 pi u by quarter turns and polynomials (warp.h), against double libm,
  // over a grid that includes every quarter's seams and both ends.
  const int n = 1 << 16;
  double worst = 0.0;
  for (int i = 0; i <= n; ++i) {
    const float u = float(i) / float(n);
    const Vec2 p = unit_circle_point(u);
    const double phi = 2.0 * M_PI * double(u);
    worst = std::max({worst, std::abs(p.x - std::cos(phi)), std::abs(p.y - std::sin(phi))});
  }
  // One float spacing near 1 is 6e-8 to 1.2e-7; a wrong quadrant or sign errs by ~1.
  EXPECT_LT(worst, 2.5e-7);
}

TEST(ChiSquare, RejectsAWrongDistribution) {
  // Guard on the guard: the test must be able to fail.
  std::vector<double> obs(10, 100.0), exp(10, 100.0);
  obs[0] = 160.0;
  obs[1] = 40.0;
  EXPECT_LT(test::chi_square_test(obs, exp).p_value, 1e-3);
  EXPECT_NEAR(test::chi_square_survival(3.84, 1), 0.05, 1e-3);
  EXPECT_NEAR(test::chi_square_survival(18.307, 10), 0.05, 1e-3);
}
