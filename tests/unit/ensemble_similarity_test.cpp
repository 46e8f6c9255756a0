// The fast forms of EMLT's similarity weights (mutations/ensemble/similarity.h) against the
// definitions they replace, and Υ's contiguous guide data (EnsembleGuides::upsilon) against
// the guide paths themselves. The guided strategies' acceptance ratios need P(n | x) to be
// the same function of the state in both directions and equal to what is sampled; the
// statistical tests check the ratios, these check the shortcuts behind them.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/mcmc/adaptive_alpha.h"
#include "emlt/mcmc/ensemble_guides.h"
#include "emlt/path/path_state.h"
#include "mutations/ensemble/guided_common.h"
#include "mutations/ensemble/similarity.h"

using namespace emlt;
using namespace emlt::ensemble;

namespace {

// eq. 8 with the library's tanh: the definition the series and the shortcuts must match.
double reference_similarity(double squared_distance, const SimilarityParams& params) {
  const double scaled = squared_distance / (params.length_scale * params.length_scale);
  return std::tanh(0.5 / std::max(scaled, params.epsilon));
}

Vec3 random_point(Rng& rng, float scale) {
  return Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f) * scale;
}

}  // namespace

TEST(EnsembleSimilarityShortcuts, EqualTanhToFloatRoundingOverEveryRange) {
  for (double length : {1.0, 0.3, 7.0}) {
    const SimilarityParams params{kPaperSimilarityEpsilon, length};
    // Squared distances from below the floor (S = 1) through the middle range (tanh) to far
    // (the series), 200 per decade.
    for (double exponent = -8.0; exponent <= 12.0; exponent += 0.005) {
      const double squared = std::pow(10.0, exponent);
      const double expected = reference_similarity(squared, params);
      const double actual = similarity_from_squared_distance(squared, params);
      // Single precision (similarity.h): f rounded to float, then a few float roundings.
      ASSERT_NEAR(actual, expected, 3e-7 * expected) << "squared distance " << squared;
      if (expected == 1.0) {
        ASSERT_EQ(actual, 1.0);
      }
    }
  }
  const SimilarityParams paper;
  EXPECT_EQ(similarity_from_squared_distance(0.0, paper), 1.0);
  EXPECT_EQ(similarity_from_squared_distance(std::numeric_limits<double>::infinity(), paper), 0.0);
  EXPECT_TRUE(std::isnan(similarity_from_squared_distance(std::nan(""), paper)));
}

TEST(EnsembleSimilarityShortcuts, RowOfGuidesEqualsVertexSimilarityBitForBit) {
  Rng rng(11, 0);
  for (double length : {1.0, 0.37}) {
    const SimilarityParams params{kPaperSimilarityEpsilon, length};
    for (int trial = 0; trial < 50; ++trial) {
      const Vec3 point = random_point(rng, 10.0f);
      // Far, middle and near guides, and one on the point itself; odd counts leave a tail
      // after the vectorised pairs.
      const size_t count = 1 + size_t(trial) % 40;
      std::vector<double> x(count), y(count), z(count), row(count);
      std::vector<Vec3> guides(count);
      for (size_t n = 0; n < count; ++n) {
        const float spread = n % 3 == 0 ? 100.0f : n % 3 == 1 ? 1.0f : 0.05f;
        guides[n] = n == 0 ? point : point + random_point(rng, spread);
        x[n] = guides[n].x;
        y[n] = guides[n].y;
        z[n] = guides[n].z;
      }
      similarities_to_guides(point, x, y, z, params, row);
      for (size_t n = 0; n < count; ++n)
        ASSERT_EQ(row[n], vertex_similarity(point, guides[n], params)) << "guide " << n;
    }
  }
}

TEST(EnsembleSimilarityShortcuts, ProductNeitherUnderflowsNorLosesDigits) {
  SimilarityProduct plain, tiny;
  double log_sum = 0.0, product = 1.0;
  for (int i = 0; i < 5; ++i) {
    const double s = 0.1 + 0.2 * i;
    plain.multiply(s);
    product *= s;
  }
  EXPECT_TRUE(plain.is_plain());
  EXPECT_EQ(plain.plain(), product);
  for (int i = 0; i < 400; ++i) {
    const double s = i % 2 ? 1e-10 : 1e-200;  // the second is kept as its log at once
    tiny.multiply(s);
    log_sum += std::log(s);
  }
  EXPECT_FALSE(tiny.is_plain());
  EXPECT_NEAR(tiny.log(), log_sum, 1e-13 * std::abs(log_sum));
  SimilarityProduct zero;
  zero.multiply(0.0);
  EXPECT_EQ(zero.log(), -std::numeric_limits<double>::infinity());
}

TEST(EnsembleSimilarityShortcuts, SelectionFromProductsEqualsSelectionFromLogs) {
  Rng rng(5, 1);
  // Plain weights, then with one vanishing (zero) or underflowing weight, which take the
  // log-weight rule.
  for (int variant = 0; variant < 3; ++variant) {
    const size_t count = 32;
    std::vector<SimilarityProduct> products(count);
    std::vector<double> logs(count);
    for (size_t n = 0; n < count; ++n) {
      products[n].multiply(std::pow(10.0, -12.0 * rng.uniform_double()));
      products[n].multiply(rng.uniform_double() + 1e-3);
    }
    if (variant == 1) products[7].multiply(0.0);
    if (variant == 2)
      for (int i = 0; i < 40; ++i) products[3].multiply(1e-9);
    for (size_t n = 0; n < count; ++n) logs[n] = products[n].log();

    for (size_t n = 0; n < count; ++n) {
      const double expected = guide_log_probability(logs, n);
      if (std::isinf(expected))  // the zero weight
        EXPECT_EQ(guide_log_probability(products, n), expected);
      else
        EXPECT_NEAR(guide_log_probability(products, n), expected, 1e-12);
    }
    std::vector<double> from_products(count), from_logs(count);
    const NormalisedWeights normalised = normalise_weights(products, from_products);
    const double effective = normalise_log_weights(logs, from_logs);
    EXPECT_TRUE(normalised.usable);
    EXPECT_NEAR(normalised.effective_guides, effective, 1e-12 * effective);
    for (size_t n = 0; n < count; ++n) EXPECT_NEAR(from_products[n], from_logs[n], 1e-14);
    // What the choice reports is the probability the reverse move evaluates.
    for (int draw = 0; draw < 200; ++draw) {
      const GuideChoice choice = choose_guide(std::span<const SimilarityProduct>(products), rng);
      ASSERT_EQ(choice.log_probability, guide_log_probability(products, choice.index));
    }
  }
  // No usable weight: uniform, and flagged for the fits.
  std::vector<SimilarityProduct> none(4);
  for (SimilarityProduct& p : none) p.multiply(0.0);
  std::vector<double> probabilities(4);
  EXPECT_FALSE(normalise_weights(none, probabilities).usable);
  EXPECT_NEAR(guide_log_probability(none, 2), std::log(0.25), 1e-12);
}

// The anisotropic fits and the guide choice form their weights as plain doubles where every
// SimilarityProduct would stay plain (faster; docs/experiments.md, "Cost per mutation"): the
// probabilities, the effective count, the
// chosen guide and its log probability must be the products' bit for bit, and the products'
// rule must decide wherever one would not stay plain (a factor or a product below
// kRenormalise, a zero, a NaN).
TEST(EnsembleSimilarityShortcuts, WeightsWithoutProductsEqualTheProductsBitForBit) {
  const auto bits = [](double v) { return std::bit_cast<uint64_t>(v); };
  Rng rng(17, 3);
  for (size_t count : {8u, 7u, 13u, 2u}) {
    for (int variant = 0; variant < 6; ++variant) {
      std::vector<double> first(count), second(count);
      for (size_t n = 0; n < count; ++n) {
        first[n] = std::pow(10.0, -14.0 * rng.uniform_double());
        second[n] = std::pow(10.0, -3.0 * rng.uniform_double());
      }
      if (variant == 1) first[1] = 1e-160;                     // a factor below kRenormalise
      if (variant == 2) first[0] = 1e-100, second[0] = 1e-60;  // their product below it
      if (variant == 3) second[count - 1] = 0.0;
      if (variant == 4) first[1] = std::numeric_limits<double>::quiet_NaN();
      if (variant == 5)
        first[0] = SimilarityProduct::kRenormalise, second[0] = 1.0;  // exactly at it
      std::vector<SimilarityProduct> products(count), alone(count);
      for (size_t n = 0; n < count; ++n) {
        products[n].multiply(first[n]);
        products[n].multiply(second[n]);
        alone[n].multiply(first[n]);
      }
      for (bool with_second : {true, false}) {
        const std::vector<SimilarityProduct>& expected_products = with_second ? products : alone;
        std::vector<double> expected(count), actual(count);
        const NormalisedWeights e = normalise_weights(expected_products, expected);
        const NormalisedWeights a = normalise_row_products(
            first, with_second ? std::span<const double>(second) : std::span<const double>(),
            actual);
        ASSERT_EQ(a.usable, e.usable) << count << " " << variant;
        ASSERT_EQ(bits(a.effective_guides), bits(e.effective_guides)) << count << " " << variant;
        for (size_t n = 0; n < count; ++n)
          ASSERT_EQ(bits(actual[n]), bits(expected[n])) << count << " " << variant << " " << n;
      }
      const bool plain = std::all_of(products.begin(), products.end(),
                                     [](auto& p) { return p.is_plain() && p.plain() > 0.0; });
      EXPECT_EQ(plain, variant == 0 || variant == 5) << variant;
      if (!plain) continue;
      std::vector<double> weights(count);
      for (size_t n = 0; n < count; ++n) weights[n] = products[n].plain();
      for (size_t n = 0; n < count; ++n)
        ASSERT_EQ(bits(guide_log_probability_from_plain(weights, n)),
                  bits(guide_log_probability(products, n)));
      for (int draw = 0; draw < 50; ++draw) {
        Rng a(100 + uint64_t(draw), 0), b(100 + uint64_t(draw), 0);
        const GuideChoice from_plain = choose_guide_from_plain(weights, a);
        const GuideChoice from_products =
            choose_guide(std::span<const SimilarityProduct>(products), b);
        ASSERT_EQ(from_plain.index, from_products.index);
        ASSERT_EQ(bits(from_plain.log_probability), bits(from_products.log_probability));
      }
    }
  }
}

namespace {

// Paths with only what EnsembleGuides reads: type, vertex kinds and positions, raster.
Path synthetic_path(Rng& rng, int vertices, uint64_t mask, bool sky) {
  Path path;
  path.vertices.resize(size_t(vertices));
  for (PathVertex& v : path.vertices) v.position = random_point(rng, 500.0f);
  if (sky) {
    path.vertices[0].kind = VertexKind::Environment;
    path.vertices[0].sky_direction = glm::normalize(random_point(rng, 1.0f) + Vec3(0, 0, 1));
  }
  path.vertices.back().raster = Vec2(rng.uniform() * 64.0f, rng.uniform() * 64.0f);
  path.type.vertices = uint8_t(vertices);
  path.type.specular_mask = mask;
  return path;
}

// A view holds M consecutive members of its type's list (cyclically, as PathTypeIndex::guides
// chooses them), each guide's own pointer, raster, positions and sky data.
void expect_window_of_members(const GuideView& view, const std::vector<const Path*>& members,
                              size_t m) {
  ASSERT_EQ(view.size(), std::min(members.size(), m));
  const size_t start = size_t(std::find(members.begin(), members.end(), view[0]) - members.begin());
  ASSERT_LT(start, members.size());
  for (size_t n = 0; n < view.size(); ++n) {
    ASSERT_EQ(view[n], members[(start + n) % members.size()]);
    const Path& guide = *view[n];
    EXPECT_EQ(view.paths()[n], &guide);
    EXPECT_EQ(view.rasters()[n], guide.raster());
    for (int i = 0; i < int(guide.vertices.size()); ++i) {
      EXPECT_EQ(view.position(n, i), guide.vertices[size_t(i)].position);
      for (int axis = 0; axis < 3; ++axis)
        EXPECT_EQ(view.coordinates(i, axis)[n], double(guide.vertices[size_t(i)].position[axis]));
      if (view.has_environment()) {
        EXPECT_EQ(view.environment(i)[n] != 0, guide.vertices[size_t(i)].is_environment());
        EXPECT_EQ(view.sky_directions(i)[n], guide.vertices[size_t(i)].sky_direction);
      }
    }
  }
}

}  // namespace

TEST(EnsembleGuideView, HoldsTheGuidePathsOwnDataForEveryWindow) {
  Rng rng(9, 2);
  std::vector<Path> paths;
  // Types of 40, 7 (fewer than M) and 1 member, one of them lit by the sky.
  for (int i = 0; i < 48; ++i) {
    const int kind = i == 47 ? 2 : i % 6 == 5 ? 1 : 0;
    paths.push_back(kind == 0   ? synthetic_path(rng, 4, 0, false)
                    : kind == 1 ? synthetic_path(rng, 5, 0b100, true)
                                : synthetic_path(rng, 3, 0, false));
  }
  std::vector<const Path*> pointers;
  for (const Path& p : paths) pointers.push_back(&p);
  pointers.push_back(nullptr);  // a chain without a seed
  EnsembleGuides ensemble;
  EnsembleParams params;
  params.selection = GuideSelection::Counter;  // lists in ensemble order
  params.neighbours = 16;
  ensemble.build(pointers, 64, 64, 3, params);
  EXPECT_EQ(ensemble.size(), paths.size());

  for (const Path* type_of : {&paths[0], &paths[5], &paths[47]}) {
    std::vector<const Path*> members;  // the type's list, in ensemble order
    for (const Path& p : paths)
      if (p.type == type_of->type) members.push_back(&p);
    for (uint64_t step = 0; step < 40; ++step) {
      const GuideView view = ensemble.counter_upsilon(type_of->type, 4, step);
      expect_window_of_members(view, members, 16);
      EXPECT_EQ(view.has_environment(), type_of == &paths[5]);
      // The same (type, chain, step): the same Υ.
      EXPECT_EQ(ensemble.counter_upsilon(type_of->type, 4, step)[0], view[0]);
    }
  }
  PathType absent;
  absent.vertices = 9;
  EXPECT_TRUE(ensemble.counter_upsilon(absent, 0, 0).empty());
}

// The layout is written in parallel, in chunks of a type's entries: types of thousands of
// members span several chunks, and a member lit by the sky in a late chunk must still mark
// its type. Built on 4 threads, every window holds its guides' own data, as built on one.
TEST(EnsembleGuideView, LargeTypesBuiltInParallelHoldTheGuidePathsOwnData) {
  Rng rng(21, 4);
  std::vector<Path> paths;
  for (int i = 0; i < 5200; ++i)
    paths.push_back(i % 2 == 0 ? synthetic_path(rng, 4, 0, i == 4800)
                               : synthetic_path(rng, 5, 0b100, false));
  std::vector<const Path*> pointers;
  for (const Path& p : paths) pointers.push_back(&p);
  EnsembleParams params;
  params.selection = GuideSelection::Counter;  // lists in ensemble order
  params.neighbours = 16;
  EnsembleGuides parallel, serial;
  tbb::task_arena(4).execute([&] { parallel.build(pointers, 64, 64, 3, params); });
  tbb::task_arena(1).execute([&] { serial.build(pointers, 64, 64, 3, params); });
  ASSERT_EQ(parallel.size(), paths.size());
  // α from every path's raster, each read once (the entries past a type's members repeat them).
  std::vector<Vec2> rasters;
  for (const Path& p : paths) rasters.push_back(p.raster());
  const double alpha = ensemble::adaptive_alpha(ensemble::image_coverage(rasters, 64, 64));
  EXPECT_EQ(std::bit_cast<uint64_t>(parallel.alpha()), std::bit_cast<uint64_t>(alpha));
  EXPECT_EQ(std::bit_cast<uint64_t>(serial.alpha()), std::bit_cast<uint64_t>(alpha));

  for (const Path* type_of : {&paths[0], &paths[1]}) {
    std::vector<const Path*> members;
    for (const Path& p : paths)
      if (p.type == type_of->type) members.push_back(&p);
    for (uint64_t chain = 0; chain < 40; ++chain)
      for (uint64_t step = 0; step < 40; ++step) {
        const GuideView view = parallel.counter_upsilon(type_of->type, chain, step);
        expect_window_of_members(view, members, 16);
        ASSERT_EQ(view.has_environment(), type_of == &paths[0]);
        // Built on one thread: the same window.
        const GuideView one = serial.counter_upsilon(type_of->type, chain, step);
        ASSERT_EQ(one[0], view[0]);
        ASSERT_EQ(one.has_environment(), view.has_environment());
      }
  }
}

// A vertex at which every guide of the type is the same point (a pinhole camera's lens
// point) has its similarity computed once instead of a row; the products must be those of
// the rows, bit for bit, whether that similarity is 1 (skipped) or not.
TEST(EnsembleGuideView, OneSimilarityWhereEveryGuideIsTheSamePoint) {
  Rng rng(13, 1);
  const Vec3 lens(1.0f, 2.0f, 3.0f);
  std::vector<Path> paths;
  for (int i = 0; i < 40; ++i) {
    // Type A (4 vertices): every lens point the same. Type B (5 vertices): one differs.
    Path path = i % 2 ? synthetic_path(rng, 4, 0, false) : synthetic_path(rng, 5, 0, false);
    path.vertices.back().position = i == 6 ? lens + Vec3(0.0f, 0.0f, 1e-3f) : lens;
    paths.push_back(path);
  }
  std::vector<const Path*> pointers;
  for (const Path& p : paths) pointers.push_back(&p);
  EnsembleGuides ensemble;
  EnsembleParams params;
  params.selection = GuideSelection::Counter;  // lists in ensemble order
  ensemble.build(pointers, 64, 64, 3, params);
  const GuideView a = ensemble.counter_upsilon(paths[1].type, 0, 0);
  const GuideView b = ensemble.counter_upsilon(paths[0].type, 0, 0);
  ASSERT_EQ(a.size(), 8u);
  EXPECT_TRUE(a.same_point(3));
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(a.same_point(i));
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(b.same_point(i));

  const SimilarityParams similarity;
  for (const Vec3 offset : {Vec3(0.0f), Vec3(0.3f, 0.0f, 0.0f), Vec3(0.0f, 40.0f, 0.0f)}) {
    Path x = synthetic_path(rng, 4, 0, false);
    x.vertices[2].position = a.position(0, 2) + Vec3(0.2f, 0.1f, 0.0f);
    x.vertices[3].position = lens + offset;
    std::vector<double> row(a.size());
    vertex_similarities(x.vertices[3], a, 3, similarity, row);
    std::vector<SimilarityProduct> products(a.size());
    path_similarities(x, a, 1, 3, similarity, products);
    for (size_t n = 0; n < a.size(); ++n) {
      const Path& guide = *a[n];
      EXPECT_EQ(row[n],
                vertex_similarity(x.vertices[3].position, guide.vertices[3].position, similarity));
      SimilarityProduct expected;
      for (int i = 1; i <= 3; ++i)
        expected.multiply(vertex_similarity(x.vertices[size_t(i)].position,
                                            guide.vertices[size_t(i)].position, similarity));
      EXPECT_EQ(products[n].is_plain(), expected.is_plain());
      EXPECT_EQ(products[n].plain(), expected.plain());
      EXPECT_EQ(products[n].log(), expected.log());
    }
  }
}

// Under MPI a rank holds the other ranks' paths as guide copies (PathCodec's guide form):
// Υ built from copies must be Υ built from the paths, field for field, or the guided steps
// (and the image) would differ from one process's.
TEST(EnsembleGuideView, GuideCopiesGiveTheSameGuidesAsThePaths) {
  Rng rng(11, 5);
  std::vector<Path> paths;
  for (int i = 0; i < 48; ++i) {
    Path path = i % 6 == 5 ? synthetic_path(rng, 5, 0b100, true) : synthetic_path(rng, 4, 0, false);
    // What the guide form leaves out, set so that a copy differs from its path there.
    for (PathVertex& v : path.vertices) {
      v.normal = random_point(rng, 1.0f);
      v.throughput = Rgb(rng.uniform());
      v.pdf_from_eye = rng.uniform();
      v.raster = Vec2(rng.uniform(), rng.uniform());
    }
    path.vertices.back().raster = Vec2(rng.uniform() * 64.0f, rng.uniform() * 64.0f);
    paths.push_back(path);
  }
  paths.push_back(Path{});  // a chain without a seed
  std::vector<Path> copies(paths.size());
  StateWriter out;
  for (const Path& path : paths) PathCodec::pack_guide(path, out);
  StateReader in(out.data());
  for (Path& copy : copies) PathCodec::unpack_guide(in, copy);
  EXPECT_EQ(in.remaining(), 0u);

  const auto build = [](const std::vector<Path>& from) {
    std::vector<const Path*> pointers;
    for (const Path& p : from) pointers.push_back(&p);
    EnsembleGuides ensemble;
    EnsembleParams params;
    params.selection = GuideSelection::Counter;  // lists in ensemble order
    params.neighbours = 8;
    ensemble.build(pointers, 64, 64, 3, params);
    return ensemble;
  };
  const EnsembleGuides original = build(paths), copied = build(copies);
  ASSERT_EQ(original.size(), copied.size());
  EXPECT_EQ(original.alpha(), copied.alpha());
  for (const Path* type_of : {&paths[0], &paths[5]})
    for (uint64_t step = 0; step < 20; ++step) {
      const GuideView a = original.counter_upsilon(type_of->type, 7, step),
                      b = copied.counter_upsilon(type_of->type, 7, step);
      ASSERT_EQ(a.size(), b.size());
      ASSERT_EQ(a.has_environment(), b.has_environment());
      for (size_t n = 0; n < a.size(); ++n) {
        EXPECT_EQ(a.rasters()[n], b.rasters()[n]);
        EXPECT_EQ(a[n]->type, b[n]->type);
        for (int i = 0; i < int(type_of->type.vertices); ++i) {
          for (int axis = 0; axis < 3; ++axis)
            EXPECT_EQ(a.coordinates(i, axis)[n], b.coordinates(i, axis)[n]);
          // Read from the paths themselves when Υ keeps no sky data (guided_common.cpp).
          EXPECT_EQ(a[n]->vertices[size_t(i)].sky_direction,
                    b[n]->vertices[size_t(i)].sky_direction);
          EXPECT_EQ(a[n]->vertices[size_t(i)].kind, b[n]->vertices[size_t(i)].kind);
          if (a.has_environment()) {
            EXPECT_EQ(a.environment(i)[n], b.environment(i)[n]);
            EXPECT_EQ(a.sky_directions(i)[n], b.sky_directions(i)[n]);
          }
        }
      }
    }
}
