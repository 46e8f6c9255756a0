// The film's reconstruction filter: camera-side samples of a pixel are distributed as the
// footprint that light-side splats give that pixel, and every footprint integrates to one
// over the image (border pixels included), so both kinds of estimator agree.
#include "emlt/film/pixel_filter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

using namespace emlt;

namespace {

// The weight pixel `target` receives from a splat at p (0 when it is not covered).
float weight_at(const PixelFilter& filter, const Vec2& p, uint32_t target) {
  float weight = 0.0f;
  filter.splat(p, [&](uint32_t pixel, float w) {
    if (pixel == target) weight += w;
  });
  return weight;
}

PixelFilterDesc gaussian(float stddev = 0.5f) {
  PixelFilterDesc desc;
  desc.kind = PixelFilterDesc::Kind::Gaussian;
  desc.stddev = stddev;
  return desc;
}

}  // namespace

TEST(PixelFilter, BoxKeepsTheUniformJitterAndOnePixel) {
  const PixelFilter box(PixelFilterDesc{}, 8, 4);
  EXPECT_TRUE(box.is_box());
  EXPECT_EQ(box.sample(3, 2, Vec2(0.25f, 0.75f)).raster, Vec2(3.25f, 2.75f));
  EXPECT_EQ(box.sample(3, 2, Vec2(0.25f, 0.75f)).weight, 1.0f);
  int visits = 0;
  box.splat(Vec2(3.5f, 1.2f), [&](uint32_t pixel, float w) {
    EXPECT_EQ(pixel, 1u * 8u + 3u);
    EXPECT_EQ(w, 1.0f);
    ++visits;
  });
  EXPECT_EQ(visits, 1);
  box.splat(Vec2(8.0f, 1.0f), [&](uint32_t, float) { ++visits; });  // outside the film
  EXPECT_EQ(visits, 1);
}

TEST(PixelFilter, GaussianHasMitsubasWindowedProfile) {
  const PixelFilter filter(gaussian(), 16, 16);
  EXPECT_FALSE(filter.is_box());
  EXPECT_EQ(filter.reach(), 2);  // radius 4 stddev = 2 pixels
  // Mitsuba's discretisation: 31 steps over the radius, each the value at its inner end.
  const float tail = std::exp(-8.0f), step = 2.0f / 31.0f;
  const auto at = [&](float t) { return std::exp(-2.0f * t * t) - tail; };
  EXPECT_NEAR(filter.density(0.01f), 1.0f - tail, 1e-6f);
  EXPECT_NEAR(filter.density(-0.01f), 1.0f - tail, 1e-6f);
  EXPECT_NEAR(filter.density(1.0f), at(15 * step), 1e-6f);   // 1.0 lies in step 15
  EXPECT_NEAR(filter.density(-1.5f), at(23 * step), 1e-6f);  // 1.5 in step 23
  EXPECT_EQ(filter.density(2.0f), 0.0f);
  EXPECT_EQ(filter.density(-2.5f), 0.0f);
}

TEST(PixelFilter, EveryFootprintIntegratesToOneInsideTheImage) {
  // Corner, edge and interior pixels of a small image, for three filters: the integral of
  // the splat weight over the image by the midpoint rule on a grid on which every step of
  // the tabulated profile begins and ends, so the sum is exact but for rounding.
  PixelFilterDesc tent;
  tent.kind = PixelFilterDesc::Kind::Tent;
  tent.radius = 1.55f;  // steps of 0.05 pixels
  for (const auto& [desc, steps] : std::vector<std::pair<PixelFilterDesc, int>>{
           {gaussian(), 62}, {gaussian(0.775f), 40}, {tent, 40}}) {
    const int width = 7, height = 5;
    const PixelFilter filter(desc, width, height);
    for (const auto& [x, y] : std::vector<std::pair<int, int>>{{0, 0}, {6, 4}, {3, 0}, {3, 2}, {1, 3}}) {
      const uint32_t target = uint32_t(y * width + x);
      double integral = 0.0;
      for (int j = 0; j < height * steps; ++j)
        for (int i = 0; i < width * steps; ++i)
          integral += weight_at(filter, Vec2((float(i) + 0.5f) / steps, (float(j) + 0.5f) / steps), target);
      EXPECT_NEAR(integral / (steps * steps), 1.0, 1e-4) << describe(desc) << " pixel " << x << "," << y;
    }
  }
}

// Mitsuba's particle tracer splats through the whole filter: a footprint integrates over the
// image to the part of it that lies inside (the tabulated profile's, as Mitsuba's table),
// one for a pixel the footprint does not overhang, and the box is the plain splat.
TEST(PixelFilter, UnrenormalisedFootprintsKeepOnlyThePartInsideTheImage) {
  const int width = 7, height = 5, steps = 62;  // every step of the profile on the grid
  const PixelFilter filter(gaussian(), width, height);
  // The fraction of the 1D profile (31 steps of 2/31 over the radius 2, each at its inner
  // end) inside the image for a pixel centred 0.5 or 1.5 from the edge.
  const auto inside = [](double from_edge) {
    const double step = 2.0 / 31.0;
    double total = 0.0, within = 0.0;
    for (int i = 0; i < 31; ++i) {
      const double value = std::exp(-2.0 * (i * step) * (i * step)) - std::exp(-8.0);
      total += 2.0 * value * step;
      within += value * step + value * std::clamp(from_edge - i * step, 0.0, step);
    }
    return within / total;
  };
  for (const auto& [x, y] :
       std::vector<std::pair<int, int>>{{0, 0}, {6, 2}, {3, 0}, {1, 4}, {3, 2}}) {
    const uint32_t target = uint32_t(y * width + x);
    double integral = 0.0;
    for (int j = 0; j < height * steps; ++j)
      for (int i = 0; i < width * steps; ++i)
        filter.splat_unrenormalised(Vec2((float(i) + 0.5f) / steps, (float(j) + 0.5f) / steps),
                                    [&](uint32_t pixel, float w) {
                                      if (pixel == target) integral += w;
                                    });
    const auto fraction = [&](int c, int size) { return inside(std::min(c, size - 1 - c) + 0.5); };
    const double expected = fraction(x, width) * fraction(y, height);
    EXPECT_NEAR(integral / (steps * steps), expected, 1e-4) << "pixel " << x << "," << y;
    if (x == 0 && y == 0) {
      EXPECT_LT(expected, 0.75);  // the corner loses more than a quarter
    }
    if (x == 3 && y == 2) {
      EXPECT_NEAR(expected, 1.0, 2e-3);
    }
  }
  const PixelFilter box(PixelFilterDesc{}, width, height);
  int visits = 0;
  box.splat_unrenormalised(Vec2(0.2f, 4.9f), [&](uint32_t pixel, float w) {
    EXPECT_EQ(pixel, 4u * 7u);
    EXPECT_EQ(w, 1.0f);
    ++visits;
  });
  EXPECT_EQ(visits, 1);
}

TEST(PixelFilter, SamplesOfAPixelAreDistributedAsItsSplatWeights) {
  // Histogram of a pixel's samples over cells of half a pixel against the splat weight
  // integrated over each cell (exactly: 31 sub-cells a cell span whole profile steps), a
  // chi-square over the cells the footprint reaches.
  const int width = 6, height = 6;
  const PixelFilter filter(gaussian(), width, height);
  for (const auto& [x, y] : std::vector<std::pair<int, int>>{{2, 3}, {0, 0}, {5, 1}}) {
    const uint32_t target = uint32_t(y * width + x);
    const int cells = 2;  // per pixel and axis
    std::map<std::pair<int, int>, int> counts;
    std::mt19937 rng(1234 + target);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const int samples = 400000;
    for (int k = 0; k < samples; ++k) {
      const Vec2 p = filter.sample(x, y, Vec2(uniform(rng), uniform(rng))).raster;
      ASSERT_TRUE(p.x >= 0.0f && p.y >= 0.0f && p.x <= float(width) && p.y <= float(height));
      ++counts[{int(p.x * cells), int(p.y * cells)}];
    }
    double chi2 = 0.0;
    int bins = 0;
    for (int cy = 0; cy < height * cells; ++cy) {
      for (int cx = 0; cx < width * cells; ++cx) {
        double expected = 0.0;
        const int sub = 31;
        for (int j = 0; j < sub; ++j)
          for (int i = 0; i < sub; ++i)
            expected += weight_at(filter, Vec2((cx + (i + 0.5f) / sub) / cells, (cy + (j + 0.5f) / sub) / cells), target);
        expected *= double(samples) / (sub * sub * cells * cells);
        const auto it = counts.find({cx, cy});
        const int observed = it == counts.end() ? 0 : it->second;
        if (expected < 5.0) {
          EXPECT_LT(observed, 40) << "cell " << cx << "," << cy;  // the footprint barely reaches it
          continue;
        }
        chi2 += (observed - expected) * (observed - expected) / expected;
        ++bins;
      }
    }
    ASSERT_GT(bins, 8);
    // Mean bins - 1, standard deviation sqrt(2 (bins - 1)): six of them above the mean.
    EXPECT_LT(chi2, bins + 6.0 * std::sqrt(2.0 * bins)) << "pixel " << x << "," << y << ": " << bins << " bins";
  }
}

TEST(PixelFilter, SplatsVisitEveryPixelTheFootprintCovers) {
  const int width = 9, height = 9;
  const PixelFilter filter(gaussian(0.7f), width, height);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (int k = 0; k < 200; ++k) {
    const Vec2 p(uniform(rng) * width, uniform(rng) * height);
    std::map<uint32_t, float> visited;
    filter.splat(p, [&](uint32_t pixel, float w) { visited[pixel] += w; });
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const float dx = p.x - (x + 0.5f), dy = p.y - (y + 0.5f);
        const bool covered = filter.density(dx) > 0.0f && filter.density(dy) > 0.0f;
        EXPECT_EQ(covered, visited.count(uint32_t(y * width + x)) == 1) << p.x << "," << p.y << " pixel " << x << "," << y;
      }
  }
}
