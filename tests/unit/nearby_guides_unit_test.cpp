// The pieces of EMLT's nearby Υ: the Hilbert order of image points, the centred window, the
// path-type lists sorted along it, the views' α and the identity of a guide across two views,
// and the tally of α that --stats reports.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/mcmc/adaptive_alpha.h"
#include "emlt/mcmc/alpha_tally.h"
#include "emlt/mcmc/ensemble_guides.h"
#include "emlt/mcmc/path_type_index.h"
#include "emlt/mcmc/raster_order.h"

using namespace emlt;

TEST(RasterOrder, HilbertIndexVisitsEveryCellOnceStepByStep) {
  for (const int bits : {1, 2, 3, 5}) {
    const uint32_t side = 1u << bits;
    std::vector<std::pair<uint32_t, uint32_t>> at(size_t(side) * side, {side, side});
    for (uint32_t y = 0; y < side; ++y)
      for (uint32_t x = 0; x < side; ++x) {
        const uint64_t d = hilbert_index(x, y, bits);
        ASSERT_LT(d, at.size());
        ASSERT_EQ(at[d].first, side) << "cell visited twice";
        at[d] = {x, y};
      }
    // Consecutive positions are neighbouring cells (what makes a window of them compact).
    for (size_t d = 1; d < at.size(); ++d) {
      const int dx = std::abs(int(at[d].first) - int(at[d - 1].first));
      const int dy = std::abs(int(at[d].second) - int(at[d - 1].second));
      ASSERT_EQ(dx + dy, 1) << "bits " << bits << " at " << d;
    }
  }
}

TEST(RasterOrder, CentredWindowStaysInsideTheList) {
  const std::vector<uint64_t> keys = {2, 4, 4, 9, 12, 30, 31, 40, 41, 50};
  EXPECT_EQ(centred_window_start(keys, 0, 4), 0u);    // before the first: clamped
  EXPECT_EQ(centred_window_start(keys, 100, 4), 6u);  // past the last: clamped
  EXPECT_EQ(centred_window_start(keys, 30, 4), 3u);   // inserted at 5: entries 3..6
  EXPECT_EQ(centred_window_start(keys, 30, 20), 0u);  // more than the list: all of it
  EXPECT_EQ(centred_window_start({}, 5, 4), 0u);
}

namespace {
Path path_at(int vertices, const Vec2& raster) {
  Path path;
  path.vertices.resize(size_t(vertices));
  for (size_t i = 0; i < path.vertices.size(); ++i)
    path.vertices[i].position = Vec3(raster.x, raster.y, float(i));
  path.vertices.back().raster = raster;
  path.type.vertices = uint8_t(vertices);
  return path;
}

// Y built from `paths` on a 64 x 64 film, Υ near the path, M = 8.
EnsembleGuides nearby_guides(const std::vector<Path>& paths) {
  std::vector<const Path*> pointers;
  for (const Path& p : paths) pointers.push_back(&p);
  EnsembleParams params;
  params.selection = GuideSelection::Nearby;
  params.neighbours = 8;
  EnsembleGuides guides;
  guides.build(pointers, 64, 64, 3, params);
  return guides;
}
}  // namespace

// Guides on a 64 x 64 film in two types: a nearby Υ holds guides of the path's type only,
// lies around the path's image point, is the same for the same point, and its α is §3.4's
// sigmoid of its own guides' bounding box.
TEST(NearbyGuides, UpsilonIsAPatchOfTheTypeAroundThePathAndCarriesItsAlpha) {
  Rng rng(5, 1);
  std::vector<Path> paths;
  for (int i = 0; i < 3000; ++i)
    paths.push_back(path_at(i % 3 ? 4 : 5, Vec2(rng.uniform() * 64.0f, rng.uniform() * 64.0f)));
  const EnsembleGuides guides = nearby_guides(paths);

  double widest = 0.0;
  std::set<const Path*> seen;
  for (int k = 0; k < 200; ++k) {
    const Path x = path_at(4, Vec2(rng.uniform() * 64.0f, rng.uniform() * 64.0f));
    const GuideView view = guides.upsilon(x, 0, uint64_t(k));
    ASSERT_EQ(view.size(), 8u);
    double farthest = 0.0;
    for (size_t n = 0; n < view.size(); ++n) {
      EXPECT_EQ(view[n]->type, x.type);
      farthest = std::max(farthest, double(glm::length(view.rasters()[n] - x.raster())));
      seen.insert(view[n]);
    }
    widest = std::max(widest, farthest);
    // A function of the path: the same point, the same Υ, whatever the step.
    EXPECT_TRUE(guides.upsilon(x, 5, 99).same_as(view));
    EXPECT_EQ(view.alpha(),
              ensemble::adaptive_alpha(ensemble::image_coverage(view.rasters(), 64, 64)));
  }
  // 2000 guides of the type on 4096 square pixels: 8 of them cover a few pixels around the
  // point, never a sizeable part of the film.
  EXPECT_LT(widest, 16.0);
  EXPECT_GT(seen.size(), 800u);
}

// A guide keeps its identity across two views of the same swap: entry n of one view is
// entry index_of(...) of another that holds it, and -1 where it does not.
TEST(NearbyGuides, GuideIdentityAcrossViews) {
  std::vector<Path> paths;
  for (int i = 0; i < 64; ++i) paths.push_back(path_at(4, Vec2(float(i) + 0.5f, 0.5f)));
  const EnsembleGuides guides = nearby_guides(paths);
  const GuideView a = guides.nearby_upsilon(paths[0].type, Vec2(20.5f, 0.5f));
  const GuideView b = guides.nearby_upsilon(paths[0].type, Vec2(23.5f, 0.5f));
  const GuideView far = guides.nearby_upsilon(paths[0].type, Vec2(60.5f, 0.5f));
  ASSERT_FALSE(a.same_as(b));
  size_t shared = 0;
  for (size_t n = 0; n < a.size(); ++n) {
    const long in_b = b.index_of(a, n);
    if (in_b >= 0) {
      EXPECT_EQ(b[size_t(in_b)], a[n]);
      ++shared;
    } else {
      for (size_t m = 0; m < b.size(); ++m) EXPECT_NE(b[m], a[n]);
    }
    EXPECT_EQ(far.index_of(a, n), -1);
  }
  EXPECT_GT(shared, 0u);
  EXPECT_LT(shared, a.size());
}

TEST(AlphaTally, QuartilesMergeAndExtremes) {
  AlphaTally a, b;
  for (int i = 0; i < 100; ++i) a.add(0.05 + 0.45 * i / 99.0);
  for (int i = 0; i < 100; ++i) b.add(0.5);
  EXPECT_EQ(a.total(), 100u);
  EXPECT_NEAR(a.quantile(0.5), 0.275, 1.0 / 256);
  EXPECT_NEAR(a.quantile(0.25), 0.16, 1.0 / 256 + 0.005);
  EXPECT_NEAR(a.min, 0.05, 1e-15);
  EXPECT_NEAR(a.max, 0.5, 1e-15);
  AlphaTally merged = a;
  merged.merge(b);
  EXPECT_EQ(merged.total(), 200u);
  EXPECT_NEAR(merged.quantile(0.75), 0.5, 1e-12);  // clamped to the exact maximum
  EXPECT_NEAR(merged.mean(), (a.sum + 50.0) / 200.0, 1e-12);
  // A fixed α reads back exactly.
  AlphaTally fixed;
  for (int i = 0; i < 10; ++i) fixed.add(0.3);
  EXPECT_EQ(fixed.quantile(0.25), 0.3);
  EXPECT_EQ(fixed.quantile(0.75), 0.3);
  EXPECT_TRUE(std::isnan(AlphaTally{}.quantile(0.5)));
}
