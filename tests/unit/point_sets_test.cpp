// The randomised unit-square point sets beside spherical Fibonacci (core/sobol_points.h,
// core/larcher_pillichshammer_points.h, core/blue_noise_points.h): Sobol's and
// Larcher-Pillichshammer's first digits against hand-worked values, the (0,m,2)-net property
// before and after random digit scrambling, and the blue-noise set's toroidal spacing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "emlt/core/blue_noise_points.h"
#include "emlt/core/larcher_pillichshammer_points.h"
#include "emlt/core/rng.h"
#include "emlt/core/sobol_points.h"

using namespace emlt;

namespace {

// True when every elementary interval of area 1/2^m, [a/2^j, (a+1)/2^j) x
// [b/2^(m-j), (b+1)/2^(m-j)) for j = 0 .. m, holds exactly one of the 2^m points.
bool is_0m2_net(const std::vector<Vec2>& points, int m) {
  const size_t n = size_t(1) << m;
  if (points.size() != n) return false;
  for (int j = 0; j <= m; ++j) {
    std::vector<int> count(n, 0);
    for (const Vec2& p : points) {
      const auto a = size_t(std::ldexp(double(p.x), j));
      const auto b = size_t(std::ldexp(double(p.y), m - j));
      ++count[(a << (m - j)) + b];
    }
    for (int c : count)
      if (c != 1) return false;
  }
  return true;
}

std::vector<Vec2> slice(const std::vector<Vec2>& v, size_t begin, size_t end) {
  return {v.begin() + std::ptrdiff_t(begin), v.begin() + std::ptrdiff_t(end)};
}

}  // namespace

// Worked by hand from the generator matrices: Sobol's second dimension has direction
// numbers 1/2, 3/4, 5/8 (Pascal's triangle mod 2), Larcher-Pillichshammer's 1/2, 3/4, 7/8
// (all ones on and above the diagonal); the van der Corput digits are the index's reversed.
TEST(PointSetDigits, FirstPointsMatchTheGeneratorMatrices) {
  const double sobol[] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
  const double lp[] = {0, 0.5, 0.75, 0.25, 0.875, 0.375, 0.125, 0.625};
  const double vdc[] = {0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
  for (uint32_t i = 0; i < 8; ++i) {
    EXPECT_EQ(std::ldexp(double(sobol_second_dimension_bits(i)), -32), sobol[i]) << i;
    EXPECT_EQ(std::ldexp(double(larcher_pillichshammer_bits(i)), -32), lp[i]) << i;
    EXPECT_EQ(std::ldexp(double(van_der_corput_bits(i)), -32), vdc[i]) << i;
  }
}

TEST(PointSetNets, SobolAndLarcherPillichshammerAreNetsBeforeAndAfterScrambling) {
  Rng rng(3, 0);
  for (int m = 0; m <= 10; ++m) {
    const uint32_t n = 1u << m;
    for (int trial = 0; trial < 4; ++trial) {
      const DigitScramble s = trial == 0 ? DigitScramble{} : DigitScramble::draw(rng);
      EXPECT_TRUE(is_0m2_net(sobol_square_points(n, s), m)) << "sobol m=" << m << " " << trial;
      EXPECT_TRUE(is_0m2_net(larcher_pillichshammer_square_points(n, s), m))
          << "larcher-pillichshammer m=" << m << " " << trial;
    }
  }
}

// At n = 384 the first points of the (0,2)-sequence are a 256-point net and a 128-point net
// (the sequence's blocks), and scrambling keeps both.
TEST(PointSetNets, SobolAtANonPowerOfTwoIsAUnionOfNets) {
  Rng rng(4, 0);
  const std::vector<Vec2> p = sobol_square_points(384, DigitScramble::draw(rng));
  EXPECT_TRUE(is_0m2_net(slice(p, 0, 256), 8));
  EXPECT_TRUE(is_0m2_net(slice(p, 256, 384), 7));
}

// A scramble is a bijection of digits, not a shift: adding a random word modulo 1 (a
// Cranley-Patterson rotation) would break the net; the check above sees that it can.
TEST(PointSetNets, TheNetCheckRejectsAShiftedNetAndARandomSet) {
  const std::vector<Vec2> net = sobol_square_points(64, {});
  std::vector<Vec2> shifted;
  for (const Vec2& p : net)
    shifted.emplace_back(std::fmod(p.x + 0.3, 1.0), std::fmod(p.y + 0.7, 1.0));
  EXPECT_FALSE(is_0m2_net(shifted, 6));
  Rng rng(5, 0);
  std::vector<Vec2> random(64);
  for (Vec2& p : random) p = rng.uniform2();
  EXPECT_FALSE(is_0m2_net(random, 6));
}

// Measured: the base sets' minimum toroidal distance relative to the densest packing's
// (hexagonal, sqrt(2 / (sqrt 3 n))) is 0.69-0.77 at n = 16 .. 1024; independent points
// reach 0.035 at n = 256 (median over 50 sets; at most 0.09). A shift modulo 1 keeps every
// toroidal distance.
TEST(BlueNoisePoints, MinimumToroidalDistanceIsLargeAndSurvivesTheShift) {
  for (uint32_t n : {16u, 64u, 256u, 384u, 1024u}) {
    const double hexagonal = std::sqrt(2.0 / (std::sqrt(3.0) * n));
    const std::vector<Vec2>& base = blue_noise_base_points(n);
    ASSERT_EQ(base.size(), n);
    const double d = min_toroidal_distance(base);
    std::printf("n = %u: minimum toroidal distance %.3f of the hexagonal packing's\n", n,
                d / hexagonal);
    EXPECT_GT(d, 0.65 * hexagonal) << n;
    const double shifted = min_toroidal_distance(blue_noise_square_points(n, {0.43f, 0.81f}));
    EXPECT_NEAR(shifted, d, 1e-5) << n;
  }
  Rng rng(6, 0);
  std::vector<Vec2> random(256);
  for (Vec2& p : random) p = rng.uniform2();
  EXPECT_LT(min_toroidal_distance(random), 0.3 * std::sqrt(2.0 / (std::sqrt(3.0) * 256)));
}

// Distances across the square's edges count: two points near opposite edges are close.
TEST(BlueNoisePoints, DistanceIsToroidal) {
  EXPECT_NEAR(min_toroidal_distance({{0.01f, 0.5f}, {0.99f, 0.5f}, {0.5f, 0.1f}}), 0.02, 1e-6);
  EXPECT_NEAR(min_toroidal_distance({{0.3f, 0.02f}, {0.3f, 0.97f}}), 0.05, 1e-6);
}
