#include "emlt/film/fixed_point_film.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <limits>
#include <thread>
#include <vector>

#include "emlt/core/rng.h"

namespace emlt {
namespace {

struct Splat {
  size_t pixel;
  DVec3 value;
};

// Values spread as the chains' are: mostly of order one, some tiny (small acceptances), a
// few large (a chain's weight carried over many rejections).
std::vector<Splat> random_splats(size_t pixels, int count) {
  Rng rng(5, 0);
  std::vector<Splat> splats;
  for (int i = 0; i < count; ++i) {
    const double scale = i % 17 == 0 ? 1e-6 : (i % 101 == 0 ? 300.0 : 1.0);
    splats.push_back(
        {size_t(rng.uniform_index(uint32_t(pixels))),
         scale * DVec3(rng.uniform_double(), rng.uniform_double(), 14.0 * rng.uniform_double())});
  }
  return splats;
}

std::vector<DVec3> totals(const std::vector<FixedPointFilm>& films, size_t pixels) {
  std::vector<DVec3> out(pixels);
  for (size_t p = 0; p < pixels; ++p) EXPECT_TRUE(FixedPointFilm::total(films, p, out[p]));
  return out;
}

TEST(FixedPointFilm, SumsDoNotDependOnOrderOrOnHowTheSplatsAreSplitBetweenFilms) {
  const size_t pixels = 64;
  std::vector<Splat> splats = random_splats(pixels, 20000);
  std::vector<FixedPointFilm> one(1, FixedPointFilm(pixels));
  for (const Splat& s : splats) one[0].add(s.pixel, s.value, false);
  // Reversed, and dealt round-robin to three films, as threads would.
  std::reverse(splats.begin(), splats.end());
  std::vector<FixedPointFilm> three(3, FixedPointFilm(pixels));
  for (size_t i = 0; i < splats.size(); ++i)
    three[i % 3].add(splats[i].pixel, splats[i].value, false);
  const std::vector<DVec3> a = totals(one, pixels), b = totals(three, pixels);
  for (size_t p = 0; p < pixels; ++p) EXPECT_EQ(a[p], b[p]) << p;  // the same bits

  // And the sums are the double sums to within the rounding of each splat (2^-25 each).
  std::vector<DVec3> exact(pixels, DVec3(0.0));
  std::vector<int> count(pixels, 0);
  for (const Splat& s : splats) exact[s.pixel] += s.value, ++count[s.pixel];
  for (size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(a[p][c], exact[p][c], count[p] * 0.5 / FixedPointFilm::kUnitsPerValue + 1e-9)
          << p;
}

TEST(FixedPointFilm, ThreadsAddingToOneSharedFilmGiveTheSequentialBits) {
  const size_t pixels = 16;  // few pixels: the threads collide on them all the time
  const std::vector<Splat> splats = random_splats(pixels, 200000);
  std::vector<FixedPointFilm> sequential(1, FixedPointFilm(pixels)),
      shared(1, FixedPointFilm(pixels));
  for (const Splat& s : splats) sequential[0].add(s.pixel, s.value, false);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (size_t i = t; i < splats.size(); i += 4)
        shared[0].add(splats[i].pixel, splats[i].value, true);
    });
  for (std::thread& thread : threads) thread.join();
  const std::vector<DVec3> a = totals(sequential, pixels), b = totals(shared, pixels);
  for (size_t p = 0; p < pixels; ++p) EXPECT_EQ(a[p], b[p]) << p;
  EXPECT_FALSE(shared[0].overflowed());
}

TEST(FixedPointFilm, OverflowIsReportedNotWrapped) {
  for (const bool shared : {false, true}) {
    SCOPED_TRACE(shared ? "shared" : "own");
    std::vector<FixedPointFilm> films(1, FixedPointFilm(2));
    const double near_the_limit = double(INT64_MAX) / FixedPointFilm::kUnitsPerValue * 0.75;
    films[0].add(1, DVec3(near_the_limit, 0.0, 0.0), shared);
    EXPECT_FALSE(films[0].overflowed());
    DVec3 sum;
    EXPECT_TRUE(FixedPointFilm::total(films, 1, sum));
    films[0].add(1, DVec3(near_the_limit, 0.0, 0.0), shared);
    EXPECT_TRUE(films[0].overflowed());
  }
  // Two films each within range whose sum is not.
  std::vector<FixedPointFilm> films(2, FixedPointFilm(1));
  const double over_half = double(INT64_MAX) / FixedPointFilm::kUnitsPerValue * 0.6;
  films[0].add(0, DVec3(0.0, over_half, 0.0), false);
  films[1].add(0, DVec3(0.0, over_half, 0.0), false);
  DVec3 sum;
  EXPECT_FALSE(FixedPointFilm::total(films, 0, sum));
  // A single value no film can hold overflows by itself, shared or not, as does a NaN.
  for (const double bad : {6e11, 1e300, std::numeric_limits<double>::quiet_NaN()})
    for (const bool shared : {false, true}) {
      std::vector<FixedPointFilm> one(1, FixedPointFilm(1));
      one[0].add(0, DVec3(0.0, 0.0, bad), shared);
      EXPECT_TRUE(one[0].overflowed()) << bad;
    }
}

TEST(FixedPointFilm, CoarserResolutionHoldsLargerTallies) {
  // The --aniso-map tallies: squared moves of up to a 4K image's width, at 2^-8 px^2.
  std::vector<FixedPointFilm> films(1, FixedPointFilm(1, 256.0));
  const double move = 3840.0 * 3840.0;
  for (int i = 0; i < 100000; ++i) films[0].add(0, DVec3(move, 0.25, 1.0), false);
  EXPECT_FALSE(films[0].overflowed());
  DVec3 sum;
  ASSERT_TRUE(FixedPointFilm::total(films, 0, sum));
  EXPECT_EQ(sum, DVec3(1e5 * move, 25000.0, 1e5));  // exact: all are multiples of 2^-8
}

}  // namespace
}  // namespace emlt
