// Reconstruction filters with negative lobes (Mitchell-Netravali, Catmull-Rom, Lanczos):
// their tabulated profile against each filter's formula (written here independently, in
// double precision), their footprints' integral over the image, the camera-side samples'
// weights against the splat weights, and the Mitsuba loader's reading of <rfilter>.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "emlt/core/error.h"
#include "emlt/film/filter_lobes.h"
#include "emlt/film/fixed_point_film.h"
#include "emlt/film/pixel_filter.h"
#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

PixelFilterDesc mitchell(float b, float c) {
  PixelFilterDesc d;
  d.kind = PixelFilterDesc::Kind::Mitchell;
  d.b = b;
  d.c = c;
  return d;
}
PixelFilterDesc catmull_rom() {
  PixelFilterDesc d;
  d.kind = PixelFilterDesc::Kind::CatmullRom;
  return d;
}
PixelFilterDesc lanczos(int lobes) {
  PixelFilterDesc d;
  d.kind = PixelFilterDesc::Kind::Lanczos;
  d.lobes = lobes;
  return d;
}

// Mitchell and Netravali (1988), eq. 8, the cubic as polynomials in |x|.
double mitchell_formula(double b, double c, double x) {
  x = std::abs(x);
  if (x < 1.0)
    return ((12 - 9 * b - 6 * c) * x * x * x + (-18 + 12 * b + 6 * c) * x * x + (6 - 2 * b)) / 6;
  if (x < 2.0)
    return ((-b - 6 * c) * x * x * x + (6 * b + 30 * c) * x * x + (-12 * b - 48 * c) * x +
            (8 * b + 24 * c)) /
           6;
  return 0.0;
}
// Catmull-Rom's spline in its own textbook form (Mitchell's B = 0, C = 1/2).
double catmull_rom_formula(double x) {
  x = std::abs(x);
  if (x < 1.0) return 1.5 * x * x * x - 2.5 * x * x + 1.0;
  if (x < 2.0) return -0.5 * x * x * x + 2.5 * x * x - 4.0 * x + 2.0;
  return 0.0;
}
double sinc(double x) {
  return x == 0.0 ? 1.0 : std::sin(M_PI * x) / (M_PI * x);
}
double lanczos_formula(int lobes, double x) {
  return std::abs(x) < lobes ? sinc(x) * sinc(x / lobes) : 0.0;
}

struct Case {
  PixelFilterDesc desc;
  float radius;
  double (*formula)(const PixelFilterDesc&, double);
};
const std::vector<Case>& cases() {
  static const std::vector<Case> all = {
      {mitchell(0.2f, 0.6f), 2.0f,
       [](const PixelFilterDesc& d, double x) { return mitchell_formula(d.b, d.c, x); }},
      {mitchell(1.0f / 3.0f, 1.0f / 3.0f), 2.0f,
       [](const PixelFilterDesc& d, double x) { return mitchell_formula(d.b, d.c, x); }},
      {catmull_rom(), 2.0f,
       [](const PixelFilterDesc&, double x) { return catmull_rom_formula(x); }},
      {lanczos(2), 2.0f,
       [](const PixelFilterDesc& d, double x) { return lanczos_formula(d.lobes, x); }},
      {lanczos(3), 3.0f,
       [](const PixelFilterDesc& d, double x) { return lanczos_formula(d.lobes, x); }},
  };
  return all;
}

float weight_at(const PixelFilter& filter, const Vec2& p, uint32_t target) {
  float weight = 0.0f;
  filter.splat(p, [&](uint32_t pixel, float w) {
    if (pixel == target) weight += w;
  });
  return weight;
}

}  // namespace

TEST(PixelFilterLobes, TablesHoldEachFormulaAtTheInnerEndOfEveryStep) {
  for (const Case& c : cases()) {
    const PixelFilter filter(c.desc, 16, 16);
    EXPECT_EQ(PixelFilter::support_radius(c.desc), c.radius) << describe(c.desc);
    EXPECT_EQ(filter.reach(), int(c.radius)) << describe(c.desc);
    // Mitsuba tabulates 31 steps over [0, radius], step k holding the value at k radius / 31.
    const double step = double(c.radius) / 31.0;
    bool negative = false;
    for (int k = 0; k < 31; ++k) {
      const double expected = c.formula(c.desc, k * step);
      for (const double inside : {0.1, 0.5, 0.9}) {
        const float t = float((k + inside) * step);
        EXPECT_NEAR(filter.density(t), expected, 2e-6) << describe(c.desc) << " step " << k;
        EXPECT_NEAR(filter.density(-t), expected, 2e-6) << describe(c.desc) << " step " << k;
      }
      negative |= expected < 0.0;
    }
    EXPECT_TRUE(negative) << describe(c.desc) << " has a negative lobe";
    EXPECT_EQ(filter.density(c.radius), 0.0f);
    EXPECT_EQ(filter.density(-c.radius - 0.3f), 0.0f);
  }
  // Known values: Mitchell's default at 0 is 8/9, Catmull-Rom interpolates (1 at 0).
  EXPECT_NEAR(PixelFilter::profile(mitchell(1.0f / 3.0f, 1.0f / 3.0f), 0.0f), 8.0 / 9.0, 1e-6);
  EXPECT_NEAR(PixelFilter::profile(catmull_rom(), 0.0f), 1.0, 1e-6);
  EXPECT_NEAR(PixelFilter::profile(catmull_rom(), 1.0f), 0.0, 1e-6);
  EXPECT_NEAR(PixelFilter::profile(lanczos(3), 1.5f), lanczos_formula(3, 1.5), 1e-6);
}

TEST(PixelFilterLobes, NegativeLobesAreKnownWhereTheTableHasThem) {
  for (const Case& c : cases()) EXPECT_TRUE(has_negative_lobes(c.desc)) << describe(c.desc);
  EXPECT_FALSE(has_negative_lobes(mitchell(1.0f, 0.0f)));  // the cubic B-spline
  EXPECT_FALSE(has_negative_lobes(PixelFilterDesc{}));
  PixelFilterDesc gaussian;
  gaussian.kind = PixelFilterDesc::Kind::Gaussian;
  EXPECT_FALSE(has_negative_lobes(gaussian));
}

TEST(PixelFilterLobes, EveryFootprintIntegratesToOneInsideTheImage) {
  // As for the positive filters: a midpoint rule on a grid on which every step of the table
  // begins and ends (62 cells a pixel for radii 2 and 3), signed weights included.
  for (const Case& c : cases()) {
    const int width = 7, height = 5, steps = 62;
    const PixelFilter filter(c.desc, width, height);
    for (const auto& [x, y] : std::vector<std::pair<int, int>>{{0, 0}, {6, 4}, {3, 0}, {3, 2}}) {
      const uint32_t target = uint32_t(y * width + x);
      double integral = 0.0, negative = 0.0;
      for (int j = 0; j < height * steps; ++j)
        for (int i = 0; i < width * steps; ++i) {
          const float w =
              weight_at(filter, Vec2((float(i) + 0.5f) / steps, (float(j) + 0.5f) / steps), target);
          integral += w;
          negative += std::min(w, 0.0f);
        }
      EXPECT_NEAR(integral / (steps * steps), 1.0, 1e-4)
          << describe(c.desc) << " pixel " << x << "," << y;
      EXPECT_LT(negative, 0.0) << describe(c.desc) << ": negative splat weights are kept";
    }
  }
}

TEST(PixelFilterLobes, WeightedSamplesOfAPixelHaveTheSplatWeightsAsExpectation) {
  // Camera-side samples fall where |footprint| is and carry sign * |integral| / integral:
  // per cell of half a pixel, the mean weight a sample leaves there must be the splat
  // weight integrated over the cell (within 5 standard errors).
  for (const Case& c : {cases()[0], cases()[3]}) {
    const int width = 6, height = 6, cells = 2, samples = 300000;
    const PixelFilter filter(c.desc, width, height);
    for (const auto& [x, y] : std::vector<std::pair<int, int>>{{2, 3}, {0, 0}}) {
      const uint32_t target = uint32_t(y * width + x);
      std::map<std::pair<int, int>, std::pair<double, double>> sums;  // weight, weight²
      std::mt19937 rng(99 + target);
      std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
      double total = 0.0;
      for (int k = 0; k < samples; ++k) {
        const FilterSample s = filter.sample(x, y, Vec2(uniform(rng), uniform(rng)));
        ASSERT_TRUE(s.raster.x >= 0.0f && s.raster.y >= 0.0f && s.raster.x <= float(width) &&
                    s.raster.y <= float(height));
        auto& cell = sums[{int(s.raster.x * cells), int(s.raster.y * cells)}];
        cell.first += s.weight;
        cell.second += double(s.weight) * s.weight;
        total += s.weight;
      }
      EXPECT_NEAR(total / samples, 1.0, 0.02) << describe(c.desc);
      int checked = 0;
      for (int cy = 0; cy < height * cells; ++cy)
        for (int cx = 0; cx < width * cells; ++cx) {
          double expected = 0.0;
          const int sub = 31;
          for (int j = 0; j < sub; ++j)
            for (int i = 0; i < sub; ++i)
              expected += weight_at(
                  filter, Vec2((cx + (i + 0.5f) / sub) / cells, (cy + (j + 0.5f) / sub) / cells),
                  target);
          expected /= double(sub * sub * cells * cells);
          const auto& [sum, sum2] = sums[{cx, cy}];
          const double mean = sum / samples;
          const double error = std::sqrt(std::max(sum2 / samples - mean * mean, 0.0) / samples);
          EXPECT_NEAR(mean, expected, 5.0 * error + 2e-4)
              << describe(c.desc) << " pixel " << x << "," << y << " cell " << cx << "," << cy;
          ++checked;
        }
      EXPECT_GT(checked, 8);
    }
  }
}

TEST(PixelFilterLobes, FixedPointFilmsAddNegativeSplats) {
  FixedPointFilm film(2);
  film.add(0, DVec3(0.75, 0.5, 2.0), false);
  film.add(0, DVec3(-0.25, -0.5, -3.0), true);
  film.add(1, DVec3(-1e-9, 0.0, 0.0), false);  // below one unit: rounds to zero
  DVec3 sum;
  ASSERT_TRUE(FixedPointFilm::total(std::span(&film, 1), 0, sum));
  EXPECT_DOUBLE_EQ(sum.x, 0.5);
  EXPECT_DOUBLE_EQ(sum.y, 0.0);
  EXPECT_DOUBLE_EQ(sum.z, -1.0);
  ASSERT_TRUE(FixedPointFilm::total(std::span(&film, 1), 1, sum));
  EXPECT_EQ(sum.x, 0.0);
  EXPECT_FALSE(film.overflowed());
}

TEST(PixelFilterLobes, MitsubaFiltersAreReadExactly) {
  const auto dir = test::scratch_dir("filters-lobes");
  const auto load = [&](const std::string& name, const std::string& rfilter) {
    const std::string xml = R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>)" +
                            rfilter + R"(</film>
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>
)";
    return load_scene_description(test::write_file(dir, name, xml));
  };
  const SceneDescription m = load("m.xml",
                                  "<rfilter type=\"mitchell\"><float name=\"B\" value=\"0.2\"/>"
                                  "<float name=\"C\" value=\"0.6\"/></rfilter>");
  EXPECT_EQ(m.verdict(), "exact");
  EXPECT_EQ(m.camera.filter.kind, PixelFilterDesc::Kind::Mitchell);
  EXPECT_FLOAT_EQ(m.camera.filter.b, 0.2f);
  EXPECT_FLOAT_EQ(m.camera.filter.c, 0.6f);
  const SceneDescription d = load("d.xml", "<rfilter type=\"mitchell\"/>");
  EXPECT_FLOAT_EQ(d.camera.filter.b, 1.0f / 3.0f);
  EXPECT_FLOAT_EQ(d.camera.filter.c, 1.0f / 3.0f);
  const SceneDescription c = load("c.xml", "<rfilter type=\"catmullrom\"/>");
  EXPECT_EQ(c.verdict(), "exact");
  EXPECT_EQ(c.camera.filter.kind, PixelFilterDesc::Kind::CatmullRom);
  const SceneDescription l =
      load("l.xml", "<rfilter type=\"lanczos\"><integer name=\"lobes\" value=\"2\"/></rfilter>");
  EXPECT_EQ(l.verdict(), "exact");
  EXPECT_EQ(l.camera.filter.kind, PixelFilterDesc::Kind::Lanczos);
  EXPECT_EQ(l.camera.filter.lobes, 2);
  EXPECT_EQ(load("l3.xml", "<rfilter type=\"lanczos\"/>").camera.filter.lobes, 3);
  EXPECT_THROW(load("bad.xml",
                    "<rfilter type=\"lanczos\"><integer name=\"lobes\" value=\"0\"/>"
                    "</rfilter>"),
               Error);
}
