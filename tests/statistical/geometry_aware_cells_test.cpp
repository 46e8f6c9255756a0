// The geometry-aware perturbations' memoised cones of quantised segments
// (mutations/geometry_aware/cone_cells.h, --gamlt-cone cells):
//  1. what the table returns is the key's own cone, and states that share a key share it;
//  2. the cone of a state does not depend on the table's history (order, thread), and a
//     table keyed without the far end's cell (an injected bug) makes it depend on it;
//  3. the cones stay near the exact ones (what the quantisation gives up);
//  4. the detailed-balance round trip of each strategy with these cones.
// Convergence against BDPT with these cones is in geometry_aware_test.cpp, beside the
// other variants'. Fixed seeds; small images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <thread>

#include "emlt/settings/settings.h"
#include "mutations/geometry_aware/cone.h"
#include "mutations/geometry_aware/cone_cells.h"
#include "mutations/geometry_aware/ga_perturbations.h"
#include "mutations/perturbation_common.h"
#include "support/mlt_test_helpers.h"
#include "support/reverse_moves.h"
#include "support/test_support.h"

using namespace emlt;
using namespace emlt::test;

namespace {

constexpr double kFraction = RenderSettings::kGamltConeCell;

struct Segment {
  const PathVertex* apex;
  const PathVertex* other;
  double alpha_min, alpha_max;
};

// Every surface or camera vertex of the paths with eight other ends: its path neighbours
// and random vertices of other paths (so that many share an apex and a level), each with
// limits drawn around the perturbations' (floors near 1e-3, ceilings from 0.01 to 1).
std::vector<Segment> segments_of(const std::vector<Path>& paths, size_t count) {
  std::vector<const PathVertex*> vertices;
  for (const Path& path : paths)
    for (const PathVertex& v : path.vertices)
      if (!v.is_environment()) vertices.push_back(&v);
  std::vector<Segment> segments;
  Rng rng(5, 2);
  for (size_t i = 0; i < vertices.size() && segments.size() < count; ++i)
    for (int k = 0; k < 8; ++k) {
      const PathVertex* other =
          k < 2 && i + 1 < vertices.size()
              ? vertices[k == 0 ? i + 1 : (i > 0 ? i - 1 : i + 1)]
              : vertices[size_t(rng.uniform() * float(vertices.size())) % vertices.size()];
      const double alpha_max = 0.01 * std::pow(100.0, double(rng.uniform()));
      if (other != vertices[i])
        segments.push_back({vertices[i], other, 1e-3 * alpha_max, alpha_max});
    }
  return segments;
}

std::vector<double> cell_cones(const Scene& scene, const std::vector<Segment>& segments,
                               bool reverse, geometry_aware::CellConeBugs bugs = {},
                               double fraction = kFraction) {
  std::vector<double> alphas(segments.size());
  for (size_t n = 0; n < segments.size(); ++n) {
    const size_t j = reverse ? segments.size() - 1 - n : n;
    const Segment& s = segments[j];
    alphas[j] = geometry_aware::cell_cone_half_angle(scene, *s.apex, *s.other, s.alpha_min,
                                                     s.alpha_max, fraction, bugs);
  }
  return alphas;
}

// A copy of v moved by `step` within its own plane (the same surface, most often the same cell).
PathVertex moved_within_plane(const PathVertex& v, double step) {
  PathVertex moved = v;
  const Frame frame(glm::normalize(v.normal));
  moved.position = Vec3(DVec3(v.position) + step * DVec3(frame.s));
  return moved;
}

// 1. The table's value is cell_key_cone's for the segment's key and the caller's limits,
// also when the entry was computed under other limits; two states with the same key (an end
// moved a little within its plane) get the same bits.
TEST(GeometryAwareCellCone, TheTableReturnsTheKeysOwnCone) {
  const auto scene = shipped_scene("door-ajar", 16);
  const auto paths = bootstrap_paths(*scene, 300, 8);
  ASSERT_GT(paths.size(), 100u);
  const std::vector<Segment> segments = segments_of(paths, 4000);
  int keyed = 0, wrong = 0, shared = 0, shared_differ = 0;
  for (const Segment& s : segments) {
    geometry_aware::CellKey key;
    if (!geometry_aware::cell_key(*scene, *s.apex, *s.other, kFraction, &key)) continue;
    ++keyed;
    const double direct = geometry_aware::cell_key_cone(*scene, key, s.alpha_min, s.alpha_max);
    if (geometry_aware::cell_cone_half_angle(*scene, *s.apex, *s.other, s.alpha_min, s.alpha_max,
                                             kFraction) != direct)
      ++wrong;
    // The same key under other limits, right after: served by the entry where it settles the
    // clamp, recomputed where not; either way the key's own value.
    // (The last pair lowers only the floor, far: an entry at its floor must not serve it.)
    for (const auto& [lo_factor, hi_factor] :
         {std::pair{0.2, 5.0}, std::pair{3.0, 1.0 / 3.0}, std::pair{0.7, 1.0 / 0.7},
          std::pair{1e-3, 1.0}}) {
      const double lo = std::min(s.alpha_min * lo_factor, 1.0),
                   hi = std::max(s.alpha_max * hi_factor, lo);
      if (geometry_aware::cell_cone_half_angle(*scene, *s.apex, *s.other, lo, hi, kFraction) !=
          geometry_aware::cell_key_cone(*scene, key, lo, hi))
        ++wrong;
    }
    if (!s.other->is_surface()) continue;
    const double length = glm::length(DVec3(s.other->position) - DVec3(s.apex->position));
    const PathVertex nearby = moved_within_plane(*s.other, 1e-3 * kFraction * length);
    geometry_aware::CellKey nearby_key;
    if (!geometry_aware::cell_key(*scene, *s.apex, nearby, kFraction, &nearby_key) ||
        !(nearby_key == key))
      continue;
    ++shared;
    if (geometry_aware::cell_cone_half_angle(*scene, *s.apex, nearby, s.alpha_min, s.alpha_max,
                                             kFraction) != direct)
      ++shared_differ;
  }
  std::printf(
      "[ info     ] %d keyed segments of %zu, %d differ from their key's cone; %d nearby states "
      "share a key, %d of them differ\n",
      keyed, segments.size(), wrong, shared, shared_differ);
  EXPECT_GT(keyed, int(segments.size() * 9 / 10));
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(shared, keyed / 2) << "a move of a thousandth of a cell mostly stays in the cell";
  EXPECT_EQ(shared_differ, 0);
}

// 2. The same state gets the same cone whatever the table held before: the segments in one
// order, in the reverse order and on a fresh thread (an empty table) give the same bits. A
// table keyed without the far end's cell returns whichever segment from the same apex cell
// filled the slot first, so the orders disagree.
TEST(GeometryAwareCellCone, SameStateSameConeWhateverTheTablesHistory) {
  const auto scene = shipped_scene("door-ajar", 16);
  const auto paths = bootstrap_paths(*scene, 300, 8);
  ASSERT_GT(paths.size(), 100u);
  const std::vector<Segment> segments = segments_of(paths, 6400);
  const auto differing = [&](geometry_aware::CellConeBugs bugs) {
    const std::vector<double> forward = cell_cones(*scene, segments, false, bugs);
    const std::vector<double> backward = cell_cones(*scene, segments, true, bugs);
    std::vector<double> fresh;
    std::thread([&] { fresh = cell_cones(*scene, segments, false, bugs); }).join();
    // This thread's table now holds the forward order's last entries: once more, forward.
    const std::vector<double> again = cell_cones(*scene, segments, false, bugs);
    int differ = 0;
    for (size_t j = 0; j < segments.size(); ++j)
      if (forward[j] != backward[j] || forward[j] != fresh[j] || forward[j] != again[j]) ++differ;
    return differ;
  };
  const int differ = differing({});
  const int differ_buggy = differing({.key_without_other_cell = true});
  std::printf(
      "[ info     ] %zu cones: %d differ between orders and threads; keyed without the far "
      "end's cell %d\n",
      segments.size(), differ, differ_buggy);
  EXPECT_EQ(differ, 0);
  EXPECT_GT(differ_buggy, int(segments.size() / 100)) << "the injected bug must show";
}

// 3. What the quantisation gives up: the cell cones of real segments against the exact ones
// under the same limits. Not a bound (cone_cells.h: the canonical segment lies up to a cell
// from the real one), but most cones must stay near the exact ones, and the share at the
// floor must not grow much (the field bound's failure, cone.h). The coarser the cells, the
// fewer stay near: at 1/4 of the segment 84-89 % of these cones are within a factor 2 of the
// exact ones, at the default 1/2 78-81 %.
TEST(GeometryAwareCellCone, CellConesStayNearTheExactCones) {
  // Both scenes alive at once: the tables know a scene by its address.
  const char* names[] = {"door-ajar", "cornell-box"};
  const std::unique_ptr<Scene> scenes[] = {shipped_scene(names[0], 16),
                                           shipped_scene(names[1], 16)};
  for (const double fraction : {0.25, kFraction})
    for (int n = 0; n < 2; ++n) {
      const std::string name = names[n];
      const auto& scene = scenes[n];
      SCOPED_TRACE(name + " at cells of " + std::to_string(fraction));
      const auto paths = bootstrap_paths(*scene, 300, 8);
      ASSERT_GT(paths.size(), 100u);
      const std::vector<Segment> segments = segments_of(paths, 4000);
      const std::vector<double> cells = cell_cones(*scene, segments, false, {}, fraction);
      int near = 0, floor_exact = 0, floor_cells = 0;
      for (size_t j = 0; j < segments.size(); ++j) {
        const Segment& s = segments[j];
        const double exact = geometry_aware::estimate_cone_half_angle(*scene, *s.apex, *s.other,
                                                                      s.alpha_min, s.alpha_max);
        if (cells[j] <= 2.0 * exact && exact <= 2.0 * cells[j]) ++near;
        floor_exact += exact <= s.alpha_min;
        floor_cells += cells[j] <= s.alpha_min;
      }
      std::printf(
          "[ info     ] %s, cells of %.2f: %zu cones, %d within a factor 2 of the exact one; at "
          "the floor: exact %d, cells %d\n",
          name.c_str(), fraction, segments.size(), near, floor_exact, floor_cells);
      EXPECT_GT(near, int(segments.size() * 3 / 4));
      EXPECT_LT(floor_cells, floor_exact + int(segments.size() / 10));
    }
}

// 4. Round trips x -> y -> x' (x' at x's positions) with the cell cones: log f(x') − log f(x)
// + r(x->y) + r(y->x') = 0, as with the exact cones (geometry_aware_test.cpp): x' lies in x's
// cells, so its cones are x's.
TEST(GeometryAwareCellCone, EveryStrategySatisfiesTheDetailedBalanceIdentity) {
  const auto scene = shipped_scene("cornell-glass", 32);
  const auto paths = bootstrap_paths(*scene, 2000, 8);
  ASSERT_GT(paths.size(), 800u);
  MutationContext ctx{*scene};
  ctx.lens_max_radius =
      std::sqrt(0.05f * float(scene->camera().width() * scene->camera().height()) / kPi);
  ctx.cone_cell_fraction = kFraction;
  const auto check = [&](const Mutation& mutation, const char* name, double noise, auto reverse) {
    std::vector<double> values;
    int proposed = 0;
    Rng rng(21, 4);
    for (const Path& x : paths) {
      if (!mutation.applies_to(x, ctx)) continue;
      const auto y = mutation.propose(x, rng, ctx);
      if (!y || !std::isfinite(y->log_reverse_over_forward) ||
          !(path_luminance(*scene, y->path) > 0.0))
        continue;
      ++proposed;
      const auto back = reverse(x, y->path);
      if (!back || !std::isfinite(back->log_reverse_over_forward)) continue;
      values.push_back(std::abs(std::log(path_luminance(*scene, back->path)) -
                                std::log(path_luminance(*scene, x)) + y->log_reverse_over_forward +
                                back->log_reverse_over_forward));
    }
    std::sort(values.begin(), values.end());
    const auto quantile = [&](double q) {
      return values.empty()
                 ? 0.0
                 : values[std::min(values.size() - 1, size_t(q * double(values.size())))];
    };
    std::printf("[ info     ] %s: %zu round trips of %d, |balance| median %.2g, 95%% %.2g\n", name,
                values.size(), proposed, quantile(0.5), quantile(0.95));
    SCOPED_TRACE(name);
    EXPECT_GT(proposed, 20);
    EXPECT_GE(int(values.size()), proposed * 9 / 10);
    EXPECT_LT(quantile(0.5), 1e-3 * noise);
    EXPECT_LT(quantile(0.95), 1e-2 * noise);
  };
  const GaLensPerturbation lens;
  check(lens, "ga-lens", 1.0,
        [&](const Path& x, const Path& y) { return lens.perturb_to(y, x.raster(), ctx); });
  const GaCausticPerturbation caustic;
  check(caustic, "ga-caustic", 1.0, [&](const Path& x, const Path& y) {
    return caustic.perturb_to(y, test::caustic_direction(x), ctx);
  });
  const GaMultiChainPerturbation multichain;
  check(multichain, "ga-multichain", 4.0, [&](const Path& x, const Path& y) {
    return multichain.perturb_to(y, x.raster(), test::multichain_directions(x), ctx);
  });
}

}  // namespace
