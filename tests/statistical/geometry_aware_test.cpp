// Geometry-aware (GAMLT-like) perturbations (mutations/geometry_aware/):
//  1. the cone estimate on constructed geometry (a sphere beside a segment: the known
//     angle), and a free-space property on real door-scene segments;
//  2. the detailed-balance round trip of each strategy on real paths, and the proposal
//     density ratio of one move against a histogram of landing points (lens, caustic,
//     multi-chain) in toy scenes where x's and y's cones differ: the injected bug (reverse
//     density with x's cones, GeometryAwareParams::reverse_uses_x_cones), invisible to the
//     round trip, is off by a factor 1.6-2 there; the same with the ratio split into the
//     part a proposal keeps and the part it defers (Proposal::deferred), and the detailed
//     balance of delayed (two-stage) acceptance on real paths, with two injected bugs;
//  3. unbiasedness of each strategy mixed with the bidirectional mutation against BDPT
//     (cornell-box, caustic-pool, cornell-glass, door-ajar).
// Fixed seeds; small images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/mlt/bootstrap.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/mcmc/delayed_acceptance.h"
#include "emlt/path/connection.h"
#include "emlt/run/progress.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "mutations/bidirectional.h"
#include "mutations/geometry_aware/cone.h"
#include "mutations/geometry_aware/ga_perturbations.h"
#include "mutations/perturbation_common.h"
#include "support/mlt_test_helpers.h"
#include "support/reverse_moves.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

using namespace emlt;
using namespace emlt::test;

namespace {

PathVertex surface_point(const Vec3& p, const Vec3& n) {
  PathVertex v;
  v.kind = VertexKind::Surface;
  v.position = p;
  v.normal = n;
  v.shading = Frame(n);
  return v;
}

// ---------------------------------------------------------------------------------------
// 1. The cone estimate.

// A segment from the floor z = 0 to the ceiling z = 4 (both large quads, the endpoints'
// own surfaces), a sphere of radius 0.5 centred 1 unit off the segment's midpoint.
std::unique_ptr<Scene> sphere_beside_segment_scene() {
  SceneDescription d;
  d.source = "sphere-beside-segment";
  const int white = test::add_material(d, make_lambertian(Rgb(0.5f)));
  test::add_quad(d, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, white, Rgb(0.0f));
  test::add_quad(d, {-10, -10, 4}, {-10, 10, 4}, {10, 10, 4}, {10, -10, 4}, white, Rgb(1.0f));
  SphereDesc sphere;
  sphere.center = Vec3(1.0f, 0.0f, 2.0f);
  sphere.radius = 0.5f;
  sphere.material = white;
  d.spheres.push_back(sphere);
  d.camera = test::camera_at(Vec3(0.0f, -5.0f, 2.0f), Vec3(0.0f, 0.0f, 2.0f), 16, Vec3(0, 0, 1));
  return Scene::build(std::move(d));
}

// Whether a ray from the apex at angle theta from the axis, azimuth phi, hits anything but
// the endpoints' own planes before it has advanced `fraction` of the segment along the axis.
bool probe_ray_blocked(const Scene& scene, const PathVertex& apex, const PathVertex& other, double theta,
                       double phi, double fraction) {
  const Vec3 axis = glm::normalize(other.position - apex.position);
  const double length = glm::length(DVec3(other.position) - DVec3(apex.position));
  const Frame frame(axis);
  const Vec3 w = glm::normalize(float(std::cos(theta)) * axis +
                                float(std::sin(theta)) * (float(std::cos(phi)) * frame.s + float(std::sin(phi)) * frame.t));
  const float scale = std::max({1.0f, glm::length(apex.position), glm::length(other.position)});
  Ray ray{apex.position, w, 0.0f, float(fraction * length / std::cos(theta))};
  for (int hops = 0; hops < 8; ++hops) {
    SurfaceHit hit;
    if (!scene.intersect(ray, hit)) return false;
    const bool own = std::abs(glm::dot(apex.normal, hit.position - apex.position)) < 2e-4f * scale ||
                     std::abs(glm::dot(other.normal, hit.position - other.position)) < 2e-4f * scale;
    if (!own) return true;
    // An endpoint's own plane: continue past it.
    const float advanced = hit.t + 1e-4f * scale;
    ray = Ray{ray.origin + advanced * ray.direction, ray.direction, 0.0f, ray.tmax - advanced};
    if (!(ray.tmax > 0.0f)) return false;
  }
  return false;
}

TEST(GeometryAwareCone, SphereBesideASegmentGivesTheKnownAngle) {
  const auto scene = sphere_beside_segment_scene();
  const PathVertex a = surface_point({0, 0, 0}, {0, 0, 1}), b = surface_point({0, 0, 4}, {0, 0, -1});
  const double alpha = geometry_aware::estimate_cone_half_angle(*scene, a, b, 1e-6, 0.5 * M_PI);
  // The exact largest free cone at apex a: the sphere's centre is atan(1/2) off the axis,
  // its angular radius asin(0.5/√5). The estimate is exact (up to rounding).
  const double exact = std::atan(0.5) - std::asin(0.5 / std::sqrt(5.0));
  std::printf("[ info     ] cone %.6f rad, exact %.6f rad\n", alpha, exact);
  EXPECT_NEAR(alpha, exact, 1e-5);
  // Symmetric geometry: the same from the other end; the own planes are not occluders.
  EXPECT_NEAR(geometry_aware::estimate_cone_half_angle(*scene, b, a, 1e-6, 0.5 * M_PI), alpha, 1e-5);
  // The cache returns the same bits.
  EXPECT_EQ(geometry_aware::cone_half_angle(*scene, a, b, 1e-6, 0.5 * M_PI), alpha);
  EXPECT_EQ(geometry_aware::cone_half_angle(*scene, a, b, 1e-6, 0.5 * M_PI), alpha);
  // Without the sphere in the way (a segment 3 units off it), the cone is much wider.
  const PathVertex c = surface_point({-3, 0, 0}, {0, 0, 1}), e = surface_point({-3, 0, 4}, {0, 0, -1});
  EXPECT_GT(geometry_aware::estimate_cone_half_angle(*scene, c, e, 1e-6, 0.5 * M_PI), 3.0 * alpha);
  // Rays inside the whole cone, over the whole span, miss the sphere; rays just outside it
  // towards the sphere hit it.
  const double span = 1.0 - geometry_aware::kConeEndMargin;
  for (int i = 0; i < 64; ++i)
    EXPECT_FALSE(probe_ray_blocked(*scene, a, b, 0.999 * alpha, 2.0 * M_PI * i / 64.0, span)) << i;
  EXPECT_TRUE(probe_ray_blocked(*scene, a, b, exact + 0.002, 0.0, span));
}

// Real segments of door-scene paths: rays from each apex anywhere within the cone (up to
// its half-angle α) must be free of occluders over the span the cone is defined on (all of
// the segment but the end margin). Segments at the floor α = 1e-6 (alpha_min) are skipped:
// the floor is not a claim (cone.h); they are segments that graze an edge, visible within
// float error (measured: 8 segments, e.g. a camera connection passing the lintel's lower
// edge at 0.3 mm). The remaining tolerance (a handful of rays in 10^4) is for rays that
// cross an endpoint's own plane within float error of another surface at the far end;
// measured 0. The first, three-probe estimate (free balls at 1/4, 1/2, 3/4 of the segment)
// fails this test: 906 of 11600 rays (7.8 %) were blocked within half its cone over 3/4 of
// the segment, and more over the whole cone and span.
TEST(GeometryAwareCone, ConesAroundDoorSceneSegmentsAreFree) {
  const auto scene = shipped_scene("door-ajar", 16);
  const auto paths = bootstrap_paths(*scene, 300, 8);
  ASSERT_GT(paths.size(), 100u);
  const double alpha_min = 1e-6, span = 1.0 - geometry_aware::kConeEndMargin;
  Rng rng(9, 1);
  int rays = 0, blocked = 0, segments = 0, narrow = 0, at_floor = 0;
  for (const Path& path : paths) {
    const auto& v = path.vertices;
    for (size_t i = 0; i + 1 < v.size(); ++i) {
      for (const bool forward : {true, false}) {
        const PathVertex& apex = forward ? v[i] : v[i + 1];
        const PathVertex& other = forward ? v[i + 1] : v[i];
        if (apex.is_environment() || other.is_environment()) continue;
        const double alpha = geometry_aware::estimate_cone_half_angle(*scene, apex, other, alpha_min, 0.5 * M_PI);
        ++segments;
        if (alpha < 0.05) ++narrow;
        if (alpha <= alpha_min) {
          ++at_floor;
          continue;
        }
        for (int r = 0; r < 4; ++r) {
          const Vec2 u = rng.uniform2();
          ++rays;
          if (probe_ray_blocked(*scene, apex, other, alpha * double(u.x), 2.0 * M_PI * double(u.y), span)) ++blocked;
        }
      }
    }
  }
  std::printf("[ info     ] %d segments (%d with α < 0.05, %d at the floor), %d rays, %d blocked\n", segments,
              narrow, at_floor, rays, blocked);
  EXPECT_GT(narrow, 0) << "the door scene must have segments near occluders";
  EXPECT_LT(at_floor, segments / 50);
  EXPECT_LE(blocked, rays / 2000);
}

// The walk's first candidate (the triangle that limited the thread's last cone from the same
// apex, cone.h) must not change any cone: every apex of door-scene bootstrap paths with
// eight other ends (its path neighbours and vertices of other paths), the cones computed in
// one order, in the reverse order (other candidates) and on a fresh thread (none at first)
// must be the same bits. Stopping the estimate at the candidate when it meets the cone (a
// throw-away edit) fails here: 2,845 of 6,407 cones differ.
TEST(GeometryAwareCone, TheWalksCandidateTriangleDoesNotChangeTheCone) {
  const auto scene = shipped_scene("door-ajar", 16);
  const auto paths = bootstrap_paths(*scene, 300, 8);
  ASSERT_GT(paths.size(), 100u);
  std::vector<const PathVertex*> vertices;
  for (const Path& path : paths)
    for (const PathVertex& v : path.vertices)
      if (!v.is_environment()) vertices.push_back(&v);
  std::vector<std::pair<const PathVertex*, const PathVertex*>> segments;
  Rng rng(5, 2);
  for (size_t i = 0; i < vertices.size() && segments.size() < 6400; ++i)
    for (int k = 0; k < 8; ++k) {
      const PathVertex* other =
          k < 2 && i + 1 < vertices.size()
              ? vertices[k == 0 ? i + 1 : (i > 0 ? i - 1 : i + 1)]
              : vertices[size_t(rng.uniform() * float(vertices.size())) % vertices.size()];
      if (other != vertices[i]) segments.push_back({vertices[i], other});
    }
  const auto cones = [&](bool reverse) {
    std::vector<double> alphas(segments.size());
    for (size_t n = 0; n < segments.size(); ++n) {
      const size_t j = reverse ? segments.size() - 1 - n : n;
      alphas[j] = geometry_aware::estimate_cone_half_angle(*scene, *segments[j].first,
                                                           *segments[j].second, 1e-6, 0.5);
    }
    return alphas;
  };
  const std::vector<double> forward = cones(false), backward = cones(true);
  std::vector<double> fresh;
  std::thread([&] { fresh = cones(false); }).join();
  int differ = 0, limited = 0;
  for (size_t j = 0; j < segments.size(); ++j) {
    if (forward[j] != backward[j] || forward[j] != fresh[j]) ++differ;
    if (forward[j] > 1e-6 && forward[j] < 0.5) ++limited;
  }
  std::printf(
      "[ info     ] %zu cones, %d limited by a surface, %d differ between orders and threads\n",
      segments.size(), limited, differ);
  EXPECT_GT(limited, int(segments.size() / 4))
      << "the candidates must matter: most cones limited by some surface";
  EXPECT_EQ(differ, 0);
}

// The clearance field's values are lower bounds on the distance to the nearest surface:
// no ray from a point may hit anything nearer. Axis-aligned rays find the Cornell box's
// walls at their true distance, so a field that lost its Lipschitz correction (the
// |p − centre| term, up to √3/2 of a cell) or its half-diagonal fails here at points near
// the walls.
TEST(GeometryAwareCone, ClearanceFieldIsALowerBoundOnTheDistanceToSurfaces) {
  for (const char* name : {"cornell-box", "door-ajar"}) {
    SCOPED_TRACE(name);
    const auto scene = shipped_scene(name, 16);
    const ClearanceField& field = scene->clearance_field();
    const Vec3 lo = scene->surface_bvh().lower(), hi = scene->surface_bvh().upper();
    Rng rng(5, 3);
    int points = 0, violations = 0, tight = 0;
    for (int i = 0; i < 4000; ++i) {
      const Vec2 uxy = rng.uniform2();
      const Vec3 p = lo + Vec3(uxy, rng.uniform()) * (hi - lo);
      double nearest = std::numeric_limits<double>::infinity();
      for (int d = 0; d < 14; ++d) {
        Vec3 w(0.0f);
        if (d < 6) {
          w[d / 2] = d % 2 ? -1.0f : 1.0f;
        } else {
          const Vec2 wxy = rng.uniform2();
          w = glm::normalize(Vec3(wxy, rng.uniform()) - 0.5f);
        }
        SurfaceHit hit;
        if (scene->intersect(Ray{p, w, 0.0f, std::numeric_limits<float>::infinity()}, hit))
          nearest = std::min(nearest, double(hit.t));
      }
      if (!std::isfinite(nearest)) continue;
      ++points;
      const double bound = field.lower_bound(DVec3(p));
      // Float rounding of the hit distance.
      if (bound > nearest + 1e-5 * (1.0 + nearest)) ++violations;
      if (bound > 0.5 * nearest) ++tight;
    }
    std::printf(
        "[ info     ] %s: %d points, %d bounds above a ray's hit, %d above half of it (cell "
        "%.4g)\n",
        name, points, violations, tight, field.cell_size());
    EXPECT_GT(points, 1000);
    EXPECT_EQ(violations, 0);
    EXPECT_GT(tight, points / 4) << "the bound must not be trivially small";
  }
}

// The cheap bound is conservative: on real segments (both directions, every segment of
// bootstrap paths) it is never wider than the exact cone. (Triangle scenes: for a sphere
// the exact walk takes the whole sphere's angle, a lower bound that the field can beat.)
// It must also be worth something: a fair share of the cones the exact walk finds wide stay
// wide.
TEST(GeometryAwareCone, FieldBoundIsNeverWiderThanTheExactCone) {
  for (const char* name : {"cornell-box", "door-ajar"}) {
    SCOPED_TRACE(name);
    const auto scene = shipped_scene(name, 16);
    const auto paths = bootstrap_paths(*scene, 300, 8);
    ASSERT_GT(paths.size(), 100u);
    int segments = 0, wider = 0, kept = 0, wide = 0, free_segments = 0, free_wider = 0;
    double worst = 0.0;
    const auto compare = [&](const PathVertex& apex, const PathVertex& other, bool on_path) {
      for (const double alpha_max : {0.05, 0.5 * M_PI}) {
        const double exact =
            geometry_aware::estimate_cone_half_angle(*scene, apex, other, 1e-6, alpha_max);
        const double field =
            geometry_aware::field_cone_half_angle(*scene, apex, other, 1e-6, alpha_max);
        worst = std::max(worst, field / exact - 1.0);
        const bool too_wide = field > exact * (1.0 + 1e-9);
        if (!on_path) {
          ++free_segments, free_wider += too_wide;
          continue;
        }
        ++segments, wider += too_wide;
        if (exact > 0.01) {
          ++wide;
          if (field > 0.5 * exact) ++kept;
        }
      }
    };
    for (const Path& path : paths) {
      const auto& v = path.vertices;
      for (size_t i = 0; i + 1 < v.size(); ++i)
        for (const bool forward : {true, false}) {
          const PathVertex& apex = forward ? v[i] : v[i + 1];
          const PathVertex& other = forward ? v[i + 1] : v[i];
          if (apex.is_environment() || other.is_environment()) continue;
          compare(apex, other, true);
        }
    }
    // Segments between random points of the scene's box: no endpoint on a surface, so the
    // cone is limited wherever the nearest surface comes, often in the field's middle span,
    // where a bound that loses a correction (the voxels' half-diagonal, the Lipschitz term
    // of the march) shows up as a cone wider than the exact one.
    const Vec3 lo = scene->surface_bvh().lower(), hi = scene->surface_bvh().upper();
    Rng rng(17, 2);
    const auto random_point = [&] {
      const Vec2 xy = rng.uniform2();
      return surface_point(lo + Vec3(xy, rng.uniform()) * (hi - lo), Vec3(0, 0, 1));
    };
    for (int i = 0; i < 3000; ++i) {
      const PathVertex a = random_point(), b = random_point();
      compare(a, b, false);
    }
    std::printf(
        "[ info     ] %s: %d path cones and %d free ones, %d and %d wider than exact (worst by "
        "%.3g), "
        "%d of %d wide ones above half\n",
        name, segments, free_segments, wider, free_wider, worst, kept, wide);
    EXPECT_EQ(wider, 0);
    EXPECT_EQ(free_wider, 0);
    // Measured: 41 % (Cornell box) and 31 % (door) of the cones wider than 0.01 keep more
    // than half their width; a bound stuck at the floor keeps none.
    EXPECT_GT(kept, wide / 5);
  }
}

// ---------------------------------------------------------------------------------------
// 2. Round trips: x -> y -> x' with x' at x's positions must satisfy
// log f(x') - log f(x) + r(x->y) + r(y->x') = 0 (r = log T(reverse)/T(forward)).

struct Balance {
  int proposed = 0, returned = 0;
  std::vector<double> values;
  double quantile(double q) const {
    std::vector<double> a;
    for (double b : values) a.push_back(std::abs(b));
    std::sort(a.begin(), a.end());
    return a.empty() ? 0.0 : a[std::min(a.size() - 1, size_t(q * double(a.size())))];
  }
};

template <typename Reverse>
Balance round_trips(const Scene& scene, const Mutation& mutation, const std::vector<Path>& paths, Reverse reverse) {
  MutationContext ctx{scene};
  ctx.lens_max_radius = std::sqrt(0.05f * float(scene.camera().width() * scene.camera().height()) / kPi);
  Balance balance;
  Rng rng(21, 4);
  for (const Path& x : paths) {
    if (!mutation.applies_to(x, ctx)) continue;
    const auto y = mutation.propose(x, rng, ctx);
    if (!y || !std::isfinite(y->log_reverse_over_forward) || !(path_luminance(scene, y->path) > 0.0)) continue;
    ++balance.proposed;
    const auto back = reverse(x, y->path, ctx);
    if (!back || !std::isfinite(back->log_reverse_over_forward)) continue;
    ++balance.returned;
    balance.values.push_back(std::log(path_luminance(scene, back->path)) - std::log(path_luminance(scene, x)) +
                             y->log_reverse_over_forward + back->log_reverse_over_forward);
  }
  return balance;
}

void expect_balanced(const Balance& b, const char* name, double noise = 1.0) {
  SCOPED_TRACE(name);
  EXPECT_GT(b.proposed, 20);
  EXPECT_GE(b.returned, b.proposed * 9 / 10);
  EXPECT_LT(b.quantile(0.5), 1e-3 * noise);
  EXPECT_LT(b.quantile(0.95), 1e-2 * noise);
  std::printf("[ info     ] %s: %d round trips, |balance| median %.2g, 95%% %.2g\n", name, b.returned,
              b.quantile(0.5), b.quantile(0.95));
}

TEST(GeometryAwareRoundTrip, EveryStrategySatisfiesTheDetailedBalanceIdentity) {
  const auto scene = shipped_scene("cornell-glass", 32);
  const auto paths = bootstrap_paths(*scene, 2000, 8);
  ASSERT_GT(paths.size(), 800u);
  const GaLensPerturbation lens;
  expect_balanced(round_trips(*scene, lens, paths, [&](const Path& x, const Path& y, const MutationContext& ctx) {
                    return lens.perturb_to(y, x.raster(), ctx);
                  }),
                  "ga-lens");
  const GaCausticPerturbation caustic;
  const auto caustic_back = [&](const Path& x, const Path& y, const MutationContext& ctx) {
    return caustic.perturb_to(y, test::caustic_direction(x), ctx);
  };
  expect_balanced(round_trips(*scene, caustic, paths, caustic_back), "ga-caustic");
  const GaMultiChainPerturbation multichain;
  const auto multichain_back = [&](const Path& x, const Path& y, const MutationContext& ctx) {
    return multichain.perturb_to(y, x.raster(), test::multichain_directions(x), ctx);
  };
  expect_balanced(round_trips(*scene, multichain, paths, multichain_back), "ga-multichain", 4.0);
}

// Delayed acceptance (include/emlt/mcmc/delayed_acceptance.h) on the same kind of round
// trips: with the ratios split as the MLT driver asks for them (ctx.may_defer), the
// two-stage acceptance P(x→y) = a1 a2 must satisfy f(x) T(x→y) P(x→y) = f(y) T(y→x) P(y→x),
// i.e. log P(x→y) − log P(y→x) = log r(x, y); each value is the difference of the two sides.
// The same proposal without deferral must carry the sum of the two parts.
template <typename Reverse>
Balance delayed_round_trips(const Scene& scene, const Mutation& mutation,
                            const std::vector<Path>& paths, Reverse reverse,
                            bool second_stage_uses_whole_ratio = false) {
  MutationContext ctx{scene};
  ctx.lens_max_radius =
      std::sqrt(0.05f * float(scene.camera().width() * scene.camera().height()) / kPi);
  ctx.may_defer = true;
  MutationContext whole_ctx = ctx;
  whole_ctx.may_defer = false;
  Balance balance;
  Rng rng(21, 4);
  int split_mismatches = 0;
  // P = a1 a2, the threshold below which the step's uniform accepts.
  const auto accept = [&](double f_from, double f_to, double first, double deferred) {
    return two_stage_decision(
               f_to / f_from * std::exp(first), 0.0, [&] { return deferred; },
               second_stage_uses_whole_ratio)
        .accept_below;
  };
  for (const Path& x : paths) {
    if (!mutation.applies_to(x, ctx)) continue;
    const auto y = mutation.propose(x, rng, ctx);
    if (!y) continue;
    const double f_x = path_luminance(scene, x), f_y = path_luminance(scene, y->path);
    if (!(f_y > 0.0)) continue;
    EXPECT_TRUE(y->deferred);
    const double deferred = mutation.deferred_log_ratio(x, *y, ctx);
    const double whole = with_deferred(y->log_reverse_over_forward, deferred);
    if (!std::isfinite(whole)) continue;
    ++balance.proposed;
    const auto back = reverse(x, y->path, ctx);
    if (!back) continue;
    const double back_deferred = mutation.deferred_log_ratio(y->path, *back, ctx);
    if (!std::isfinite(with_deferred(back->log_reverse_over_forward, back_deferred))) continue;
    ++balance.returned;
    const auto undivided = reverse(x, y->path, whole_ctx);
    if (!undivided ||
        !(std::abs(undivided->log_reverse_over_forward -
                   with_deferred(back->log_reverse_over_forward, back_deferred)) < 1e-12))
      ++split_mismatches;
    const double forward = accept(f_x, f_y, y->log_reverse_over_forward, deferred);
    const double backward = accept(f_y, path_luminance(scene, back->path),
                                   back->log_reverse_over_forward, back_deferred);
    balance.values.push_back(std::log(forward) - std::log(backward) -
                             (std::log(f_y) - std::log(f_x) + whole));
  }
  EXPECT_EQ(split_mismatches, 0) << "the two parts must add up to the undivided ratio";
  return balance;
}

const auto kLensBack = [](const GaLensPerturbation& lens) {
  return [&lens](const Path& x, const Path& y, const MutationContext& ctx) {
    return lens.perturb_to(y, x.raster(), ctx);
  };
};

// Measured on cornell-glass 32x32 (|imbalance| over the round trips, median and 95 %): ga-lens
// 3e-15 and 2.6e-4, ga-caustic 3e-5 and 1.4e-3, ga-multichain 3e-6 and 2e-3 (the base
// moves' own round-trip rounding, as in the test above); the second stage with the whole
// ratio (a2 = min(1, r)) 0.15 and 2.9; x's range normalisation in the first stage 0.15 and
// 1.5.
TEST(GeometryAwareRoundTrip, DelayedAcceptanceSatisfiesDetailedBalanceAndCatchesTwoInjectedBugs) {
  const auto scene = shipped_scene("cornell-glass", 32);
  const auto paths = bootstrap_paths(*scene, 2000, 8);
  ASSERT_GT(paths.size(), 800u);
  const GaLensPerturbation lens;
  expect_balanced(delayed_round_trips(*scene, lens, paths, kLensBack(lens)), "ga-lens, delayed");
  const GaCausticPerturbation caustic;
  const auto caustic_back = [&](const Path& x, const Path& y, const MutationContext& ctx) {
    return caustic.perturb_to(y, test::caustic_direction(x), ctx);
  };
  expect_balanced(delayed_round_trips(*scene, caustic, paths, caustic_back), "ga-caustic, delayed");
  const GaMultiChainPerturbation multichain;
  const auto multichain_back = [&](const Path& x, const Path& y, const MutationContext& ctx) {
    return multichain.perturb_to(y, x.raster(), test::multichain_directions(x), ctx);
  };
  expect_balanced(delayed_round_trips(*scene, multichain, paths, multichain_back),
                  "ga-multichain, delayed", 4.0);

  // The driver's bug: the second stage with the whole ratio counts the first stage's twice.
  const Balance whole_twice = delayed_round_trips(*scene, lens, paths, kLensBack(lens), true);
  std::printf("[ info     ] second stage with the whole ratio: |balance| median %.2g, 95%% %.2g\n",
              whole_twice.quantile(0.5), whole_twice.quantile(0.95));
  EXPECT_GT(whole_twice.quantile(0.5), 0.05) << "the injected bug must be off by a clear margin";
  // The strategy's bug: x's range normalisation kept in the first stage, whose ratio is then
  // not inverted by exchanging x and y (the whole ratio is unchanged).
  GeometryAwareParams split_wrong;
  split_wrong.stage_one_keeps_x_range = true;
  const GaLensPerturbation wrong_lens(split_wrong);
  const Balance x_range_first =
      delayed_round_trips(*scene, wrong_lens, paths, kLensBack(wrong_lens));
  std::printf("[ info     ] x's range in the first stage: |balance| median %.2g, 95%% %.2g\n",
              x_range_first.quantile(0.5), x_range_first.quantile(0.95));
  EXPECT_GT(x_range_first.quantile(0.5), 0.05) << "the injected bug must be off by a clear margin";
}

// ---------------------------------------------------------------------------------------
// 2b. Proposal densities against a histogram of landing points. The round trip cannot see
// a reverse density evaluated with x's cones (the two wrong terms cancel over x -> y -> x);
// the density ratio of one move can. Toy scene: a floor (y = 0), a small light above it,
// a camera looking down at the floor and a sphere beside the eye rays, so that R(z) (the
// ga-lens range, limited by the eye ray's free cone) grows quickly with z's raster distance
// from the sphere. x's eye ray passes close to the sphere, y's a step further away.

std::unique_ptr<Scene> floor_beside_sphere_scene() {
  SceneDescription d;
  d.source = "floor-beside-sphere";
  const int white = test::add_material(d, make_lambertian(Rgb(0.7f)));
  test::add_quad(d, {-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, white, Rgb(0.0f));  // faces +y
  const float h = 0.3f, s = 0.01f;
  test::add_quad(d, {-s, h, -s}, {s, h, -s}, {s, h, s}, {-s, h, s}, white, Rgb(50.0f));  // faces -y
  SphereDesc sphere;
  sphere.center = Vec3(0.15f, 0.75f, -1.25f);
  sphere.radius = 0.1f;
  sphere.material = white;
  d.spheres.push_back(sphere);
  d.camera = test::camera_at(Vec3(0.0f, 1.5f, -2.5f), Vec3(0.0f, 0.0f, 0.0f), 32);
  return Scene::build(std::move(d));
}

struct DensityEvidence {
  double measured = 0.0;  // T(x->y)/T(y->x) from the landing histograms
  double reported = 0.0;  // exp(−log_reverse_over_forward) of the move x -> y
  double buggy = 0.0;     // the same with reverse_uses_x_cones
  // The same two with the ratio split as the MLT driver asks for it (ctx.may_defer): the
  // proposal's part and the deferred one, added.
  double split = 0.0, split_buggy = 0.0;
};

// exp(−log T(y→x)/T(x→y)) of a proposal made with ctx.may_defer, its deferred part added.
template <typename Strategy>
double split_ratio(const Strategy& strategy, const Path& x, const std::optional<Proposal>& y,
                   const MutationContext& ctx) {
  EXPECT_TRUE(y.has_value());
  if (!y) return 0.0;
  EXPECT_TRUE(y->deferred);
  return std::exp(
      -with_deferred(y->log_reverse_over_forward, strategy.deferred_log_ratio(x, *y, ctx)));
}

// x -> y by `move(mutation, x, ctx)` (a deterministic perturb_to), then the histograms of both
// directions and the ratio the correct and the buggy variant report, whole and split.
template <typename Strategy, typename Move>
DensityEvidence density_evidence(const Scene& scene, const MutationContext& ctx, GeometryAwareParams params,
                                 const Path& x, Move move) {
  const Strategy strategy(params);
  MutationContext deferring = ctx;
  deferring.may_defer = true;
  const auto y = move(strategy, x, ctx);
  EXPECT_TRUE(y.has_value());
  if (!y) return {};
  EXPECT_GT(path_luminance(scene, y->path), 0.0);
  const float radius = 0.03f;
  const int proposals = 400000;
  int hits_forward = 0, hits_reverse = 0;
  DensityEvidence e;
  const double forward =
      landing_density(strategy, x, 1, y->path.vertices[1].position, radius, proposals, ctx, 11, &hits_forward);
  const double reverse =
      landing_density(strategy, y->path, 1, x.vertices[1].position, radius, proposals, ctx, 12, &hits_reverse);
  EXPECT_GT(hits_reverse, 1000) << "too few landings for a density estimate";
  EXPECT_GT(hits_forward, 1000) << "too few landings for a density estimate";
  e.measured = forward / reverse;
  e.reported = std::exp(-y->log_reverse_over_forward);
  e.split = split_ratio(strategy, x, move(strategy, x, deferring), deferring);
  params.reverse_uses_x_cones = true;
  const Strategy buggy_strategy(params);
  const auto buggy = move(buggy_strategy, x, ctx);
  EXPECT_TRUE(buggy.has_value());
  if (buggy) e.buggy = std::exp(-buggy->log_reverse_over_forward);
  e.split_buggy = split_ratio(buggy_strategy, x, move(buggy_strategy, x, deferring), deferring);
  std::printf(
      "[ info     ] T(x->y)/T(y->x): histogram %.4f (%d, %d landings), reported %.4f, with x's "
      "cones %.4f; "
      "split %.4f, %.4f\n",
      e.measured, hits_forward, hits_reverse, e.reported, e.buggy, e.split, e.split_buggy);
  return e;
}

MutationContext floor_sphere_context(const Scene& scene) {
  MutationContext ctx{scene};
  ctx.lens_min_radius = 0.5f;
  ctx.lens_max_radius = 12.0f;
  return ctx;
}

// The ranges these tests were built for: the lens radius limited by the eye ray's cone
// (the sphere below stands beside the eye rays), no floor and Veach's ceiling, so that the
// ranges follow the cones over the whole of [3 r1, r2]. (With the defaults' floor, half of
// Veach's largest step, R(x) and R(y) would both sit at the floor here.) c = 4: between two
// points a step apart, a range limited by a free cone can grow by at most a factor 1 + c
// (the cone's edge moves by the step), so R(x) and R(y) differ by a factor ~4, and the
// ratio of the ln terms the bug drops is ~2.
GeometryAwareParams wide_steps() {
  GeometryAwareParams params;
  params.step_scale = 4.0;
  params.floor = 0.0;
  params.ceiling = 1.0;
  params.eye_cone = true;
  return params;
}

// x's eye ray passes the sphere 1.0 px from its silhouette, y's 2.5 px: R(x) = 2.0 px,
// R(y) = 7.9 px (r1 = 0.5 px), so log T(y→x)/T(x→y) carries ln ln(R(x)/r1) − ln ln(R(y)/r1)
// = ln(1.39/2.76): a factor ~2 that the bug drops. Measured: histogram 2.00 (2981 and 1487
// landings), reported 1.99, with x's cones 1.00. (The test checks the density bookkeeping,
// whatever the cone estimate: the same holds with the first, three-probe estimate.)
TEST(GeometryAwareDensity, LensRatioMatchesTheHistogramAndCatchesTheInjectedBug) {
  const auto scene = floor_beside_sphere_scene();
  const MutationContext ctx = floor_sphere_context(*scene);
  const Path x = light_floor_eye_path(*scene, Vec2(15.5f, 16.5f));
  ASSERT_EQ(x.type.to_string(), "L D E");
  ASSERT_GT(path_luminance(*scene, x), 0.0);
  const auto move = [&](const GaLensPerturbation& lens, const Path& from,
                        const MutationContext& c) {
    return lens.perturb_to(from, from.raster() + Vec2(1.5f, 0.0f), c);
  };
  const auto y = move(GaLensPerturbation(wide_steps()), x, ctx);
  ASSERT_TRUE(y.has_value());
  const GaLensPerturbation lens(wide_steps());
  const double r_x = lens.max_radius(x, ctx), r_y = lens.max_radius(y->path, ctx);
  std::printf("[ info     ] R(x) %.3f px, R(y) %.3f px, r1 %.2f px\n", r_x, r_y, double(ctx.lens_min_radius));
  EXPECT_GT(r_y, 3.0 * r_x) << "the scene must make the two ranges differ clearly";
  const auto e = density_evidence<GaLensPerturbation>(*scene, ctx, wide_steps(), x, move);
  EXPECT_NEAR(e.measured / e.reported, 1.0, 0.1);
  EXPECT_GT(std::abs(e.measured / e.buggy - 1.0), 0.5) << "the injected bug must be off by a clear margin";
  EXPECT_NEAR(e.measured / e.split, 1.0, 0.1);
  EXPECT_GT(std::abs(e.measured / e.split_buggy - 1.0), 0.5) << "and so with the ratio split";
}

// The same for the caustic perturbation: the light's direction turns towards the floor
// point y the lens test moves to. Θ(z) is limited by the eye ray's cone (seen through
// d_eye/L_chain), so Θ(x) < Θ(y) as R(x) < R(y) above. Measured: Θ(x) 0.64, Θ(y) 1.57
// (Veach's θ2) with θ1 0.16; histogram 1.47, reported 1.50, with x's cones 0.90.
TEST(GeometryAwareDensity, CausticRatioMatchesTheHistogramAndCatchesTheInjectedBug) {
  const auto scene = floor_beside_sphere_scene();
  const MutationContext ctx = floor_sphere_context(*scene);
  const Path x = light_floor_eye_path(*scene, Vec2(15.5f, 16.5f));
  const Path target = light_floor_eye_path(*scene, Vec2(17.0f, 16.5f));
  const Vec3 direction = direction_between(target.vertices[0], target.vertices[1]);
  const auto move = [&](const GaCausticPerturbation& caustic, const Path& from,
                        const MutationContext& c) {
    return caustic.perturb_to(from, direction, c);
  };
  const GaCausticPerturbation caustic(wide_steps());
  ASSERT_TRUE(caustic.applies_to(x, ctx));
  double min_x = 0.0, max_x = 0.0, min_y = 0.0, max_y = 0.0;
  caustic.angle_range(x, ctx, &min_x, &max_x);
  caustic.angle_range(target, ctx, &min_y, &max_y);
  std::printf("[ info     ] θ1 %.4f, Θ(x) %.4f, Θ(y) %.4f rad\n", min_x, max_x, max_y);
  const auto e = density_evidence<GaCausticPerturbation>(*scene, ctx, wide_steps(), x, move);
  EXPECT_NEAR(e.measured / e.reported, 1.0, 0.1);
  EXPECT_GT(std::abs(e.measured / e.buggy - 1.0), 0.3) << "the injected bug must be off by a clear margin";
  EXPECT_NEAR(e.measured / e.split, 1.0, 0.1);
  EXPECT_GT(std::abs(e.measured / e.split_buggy - 1.0), 0.3) << "and so with the ratio split";
}

// x's segment x3 -> x2 runs from (-0.039, 0, -0.385) to (-0.039, 1, 1.315); the sphere
// (radius 0.05) stands 0.054 beside its midpoint; -4 pixels move the seen point 0.31
// away from it (+x).
constexpr float kAwayPixels = -4.0f;
constexpr double kMultiChainTheta1 = 0.005, kMultiChainTheta2 = 0.04;

// Multi-chain: the shortest path of its form, L D S D E. The camera sees the floor (x3),
// the direction at x3 goes up to a downward-facing mirror (x2) and back down to the floor
// (x1), lit by a small light just above (x0). A sphere stands beside the segment x3 -> x2,
// so that Θ(z), the range of the angular step at x3 (limited by that segment's cone),
// is small for x, whose segment passes the sphere at 4 mm, and at its ceiling for y,
// whose seen point is 4 pixels further away from it.
std::unique_ptr<Scene> floor_mirror_sphere_scene() {
  SceneDescription d = test::floor_mirror_description();
  d.source = "floor-mirror-sphere";
  SphereDesc sphere;
  sphere.center = Vec3(-0.093f, 0.5f, 0.465f);
  sphere.radius = 0.05f;
  sphere.material = 0;  // the floor's white
  d.spheres.push_back(sphere);
  return Scene::build(std::move(d));
}

// The move's two variables are independent (the image offset, then the direction at the
// new seen point drawn around the old one), so its density over (x3, x1) factors into the
// density of the seen point and that of x1 given the seen point: the first from image
// offsets drawn with R(from) (where they land on the floor), the second from the angular
// step with Θ(from) taken at the destination's image point, through the strategy's own
// perturb_to. Each is a histogram of landing points.
double seen_point_density(const Scene& scene, const GaMultiChainPerturbation& strategy, const Path& from,
                          const Path& to, const MutationContext& ctx, uint64_t seed) {
  const float radius = 0.08f;
  const int samples = 1000000;
  const float r_max = float(strategy.max_radius(from, ctx));
  Rng rng(seed, 7);
  int hits = 0;
  for (int i = 0; i < samples; ++i) {
    const Vec2 raster = from.raster() + perturbation::sample_image_offset(ctx.lens_min_radius, r_max, rng.uniform2());
    SurfaceHit hit;
    if (scene.intersect(scene.camera().generate_ray(raster, Vec2(0.5f)), hit) &&
        glm::length(hit.position - to.vertices[3].position) < radius)
      ++hits;
  }
  EXPECT_GT(hits, 2000) << "too few landings for a density estimate";
  return double(hits) / (double(samples) * kPi * double(radius) * double(radius));
}

double lit_point_density(const GaMultiChainPerturbation& strategy, const Path& from, const Path& to,
                         const MutationContext& ctx, uint64_t seed) {
  const float radius = 0.01f;
  const int samples = 400000;
  const Vec3 old_direction = direction_between(from.vertices[3], from.vertices[2]);
  const double theta_max = strategy.angle_limits(from, ctx).at(0);
  Rng rng(seed, 7);
  int hits = 0;
  for (int i = 0; i < samples; ++i) {
    const Vec3 direction = perturbation::perturb_direction(old_direction, kMultiChainTheta1, theta_max, rng.uniform2());
    const auto y = strategy.perturb_to(from, to.raster(), {direction}, ctx);
    if (y && glm::length(y->path.vertices[1].position - to.vertices[1].position) < radius) ++hits;
  }
  EXPECT_GT(hits, 2000) << "too few landings for a density estimate";
  return double(hits) / (double(samples) * kPi * double(radius) * double(radius));
}

// x's segment x3 -> x2 passes the sphere at an angle α(x) ≈ 0.004 rad seen from x3, so
// Θ(x) = c α(x) ≈ 0.016; y's seen point is 4 pixels further away, Θ(y) at the ceiling
// 0.04 (θ1 = 0.005): log T(y→x)/T(x→y) carries ln ln(Θ(x)/θ1) − ln ln(Θ(y)/θ1), a factor
// ~1.8 that the bug drops. The image range is the same for both (lo = hi = 5.5 px), so the
// difference is the angular step's alone. Measured: Θ(x) 0.0154, Θ(y) 0.040; histogram
// 1.94, reported 1.95, with x's cones 1.05.
TEST(GeometryAwareDensity, MultiChainRatioMatchesTheHistogramAndCatchesTheInjectedBug) {
  const auto scene = floor_mirror_sphere_scene();
  MutationContext ctx{*scene};
  ctx.lens_min_radius = 3.0f;
  ctx.lens_max_radius = 5.5f;
  const GeometryAwareParams params = wide_steps();
  const GaMultiChainPerturbation multichain(params, kMultiChainTheta1, kMultiChainTheta2);
  const Path x = test::floor_mirror_light_path(*scene, Vec2(16.5f, 16.5f), glm::normalize(Vec3(0.0f, 1.0f, 1.7f)));
  ASSERT_EQ(x.type.to_string(), "L D S D E");
  ASSERT_GT(path_luminance(*scene, x), 0.0);
  ASSERT_TRUE(multichain.applies_to(x, ctx));

  // y: the image point 4 pixels away from the sphere, the direction at the seen point turned by 0.01 rad.
  const Vec3 x_direction = direction_between(x.vertices[3], x.vertices[2]);
  const Vec3 axis = glm::normalize(glm::cross(x_direction, Vec3(1, 0, 0)));
  const Vec3 y_direction = glm::normalize(x_direction * std::cos(0.01f) + axis * std::sin(0.01f));
  const Vec2 y_raster = x.raster() + Vec2(kAwayPixels, 0.0f);
  const auto y = multichain.perturb_to(x, y_raster, {y_direction}, ctx);
  ASSERT_TRUE(y.has_value());
  ASSERT_TRUE(std::isfinite(y->log_reverse_over_forward));
  const Path& yp = y->path;
  ASSERT_EQ(yp.type.to_string(), "L D S D E");
  const double theta_x = multichain.angle_limits(x, ctx).at(0), theta_y = multichain.angle_limits(yp, ctx).at(0);
  std::printf("[ info     ] Θ(x) %.4f, Θ(y) %.4f rad (θ1 %.3f); R(x) %.2f, R(y) %.2f px\n", theta_x, theta_y,
              kMultiChainTheta1, multichain.max_radius(x, ctx), multichain.max_radius(yp, ctx));
  EXPECT_GT(theta_y, 1.8 * theta_x) << "the scene must make the two ranges differ clearly";

  const double forward = seen_point_density(*scene, multichain, x, yp, ctx, 11) *
                         lit_point_density(multichain, x, yp, ctx, 12);
  const double reverse = seen_point_density(*scene, multichain, yp, x, ctx, 13) *
                         lit_point_density(multichain, yp, x, ctx, 14);
  const double measured = forward / reverse;  // T(x->y) / T(y->x) over floor area
  const double to_area = std::exp(test::log_floor_area_per_nu(x) - test::log_floor_area_per_nu(yp));
  const double reported = std::exp(-y->log_reverse_over_forward) * to_area;
  GeometryAwareParams buggy_params = params;
  buggy_params.reverse_uses_x_cones = true;
  const auto buggy = GaMultiChainPerturbation(buggy_params, kMultiChainTheta1, kMultiChainTheta2)
                         .perturb_to(x, y_raster, {y_direction}, ctx);
  ASSERT_TRUE(buggy.has_value());
  const double reported_buggy = std::exp(-buggy->log_reverse_over_forward) * to_area;
  // Split as the MLT driver asks for it: the proposal's part and the deferred one.
  MutationContext deferring = ctx;
  deferring.may_defer = true;
  const GaMultiChainPerturbation buggy_multichain(buggy_params, kMultiChainTheta1,
                                                  kMultiChainTheta2);
  const double split =
      split_ratio(multichain, x, multichain.perturb_to(x, y_raster, {y_direction}, deferring),
                  deferring) *
      to_area;
  const double split_buggy =
      split_ratio(buggy_multichain, x,
                  buggy_multichain.perturb_to(x, y_raster, {y_direction}, deferring), deferring) *
      to_area;
  std::printf(
      "[ info     ] T(x->y)/T(y->x): histogram %.4f, reported %.4f, with x's cones %.4f (nu->area "
      "%.4f); "
      "split %.4f, %.4f\n",
      measured, reported, reported_buggy, to_area, split, split_buggy);
  EXPECT_NEAR(measured / reported, 1.0, 0.1);
  EXPECT_GT(std::abs(measured / reported_buggy - 1.0), 0.3) << "the injected bug must be off by a clear margin";
  EXPECT_NEAR(measured / split, 1.0, 0.1);
  EXPECT_GT(std::abs(measured / split_buggy - 1.0), 0.3) << "and so with the ratio split";
}

// ---------------------------------------------------------------------------------------
// 3. Unbiasedness against BDPT.

TEST(GeometryAwareUnbiased, LensMixConvergesToBdptOnTheCornellBox) {
  const auto scene = shipped_scene("cornell-box", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  MltStatistics stats;
  const Image image = mlt_image(*scene, "bidir=1,ga-lens=4", 8000, &stats);
  EXPECT_GT(share_of(stats, "ga-lens"), 0.4);
  expect_converged_to(image, reference, 2, 0.06, 0.04);
}

// Delayed (two-stage) acceptance (--gamlt-acceptance delayed) on the same scene and budget.
TEST(GeometryAwareUnbiased, LensMixWithDelayedAcceptanceConvergesToBdptOnTheCornellBox) {
  const auto scene = shipped_scene("cornell-box", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  MltStatistics stats;
  const Image image =
      mlt_image(*scene, "bidir=1,ga-lens=4", 8000, &stats, {.delayed_acceptance = true});
  EXPECT_GT(share_of(stats, "ga-lens"), 0.4);
  expect_converged_to(image, reference, 2, 0.06, 0.04);
}

// The cheap conservative cones (--gamlt-cone field) on the same scene and budget.
TEST(GeometryAwareUnbiased, LensMixWithTheFieldConesConvergesToBdptOnTheCornellBox) {
  const auto scene = shipped_scene("cornell-box", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  MltStatistics stats;
  const Image image = mlt_image(*scene, "bidir=1,ga-lens=4", 8000, &stats, {.field_cone = true});
  EXPECT_GT(share_of(stats, "ga-lens"), 0.4);
  expect_converged_to(image, reference, 2, 0.06, 0.04);
}

// The exact walk for every segment (--gamlt-cone exact; the default memoises the cones of
// quantised segments) on the same scene and budget.
TEST(GeometryAwareUnbiased, LensMixWithTheExactConesConvergesToBdptOnTheCornellBox) {
  const auto scene = shipped_scene("cornell-box", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  MltStatistics stats;
  const Image image = mlt_image(*scene, "bidir=1,ga-lens=4", 8000, &stats, {.cone_cells = 0.0});
  EXPECT_GT(share_of(stats, "ga-lens"), 0.4);
  expect_converged_to(image, reference, 2, 0.06, 0.04);
}

TEST(GeometryAwareUnbiased, CausticMixConvergesToBdptOnTheCausticPool) {
  const auto scene = shipped_scene("caustic-pool", 16);
  const Image reference = bdpt_reference(*scene, 2048);
  MltStatistics stats;
  const Image image = mlt_image(*scene, "bidir=1,ga-caustic=4", 4000, &stats);
  EXPECT_GT(share_of(stats, "ga-caustic"), 0.2);
  expect_converged_to(image, reference, 2, 0.12, 0.05);
}

TEST(GeometryAwareUnbiased, CausticMixWithDelayedAcceptanceConvergesToBdptOnTheCausticPool) {
  const auto scene = shipped_scene("caustic-pool", 16);
  const Image reference = bdpt_reference(*scene, 2048);
  MltStatistics stats;
  const Image image =
      mlt_image(*scene, "bidir=1,ga-caustic=4", 4000, &stats, {.delayed_acceptance = true});
  EXPECT_GT(share_of(stats, "ga-caustic"), 0.2);
  expect_converged_to(image, reference, 2, 0.12, 0.05);
}

TEST(GeometryAwareUnbiased, MultiChainMixConvergesToBdptThroughGlass) {
  const auto scene = shipped_scene("cornell-glass", 16);
  const Image reference = bdpt_reference(*scene, 2048);
  MltStatistics stats;
  const Image image = mlt_image(*scene, "bidir=1,ga-lens=1,ga-multichain=4", 3000, &stats);
  EXPECT_GT(share_of(stats, "ga-multichain"), 0.005);
  expect_converged_to(image, reference, 2, 0.12, 0.05);
}

TEST(GeometryAwareUnbiased, MultiChainMixWithDelayedAcceptanceConvergesToBdptThroughGlass) {
  const auto scene = shipped_scene("cornell-glass", 16);
  const Image reference = bdpt_reference(*scene, 2048);
  MltStatistics stats;
  const Image image = mlt_image(*scene, "bidir=1,ga-lens=1,ga-multichain=4", 3000, &stats,
                                {.delayed_acceptance = true});
  EXPECT_GT(share_of(stats, "ga-multichain"), 0.005);
  expect_converged_to(image, reference, 2, 0.12, 0.05);
}

// At 8000 mutations per pixel, twice the budget of the tests below: at 4000 the worst quadrant
// is off by 0.04-0.16 over seeds 1-5 with the default cones (cells of 1/2), 0.07-0.22 with the
// exact ones, 0.08-0.20 and 0.09-0.25 under delayed acceptance (command-line renders of this
// scene at the test's settings), so the tolerance sits inside the seeds' spread for every
// variant, and the test of the default and its delayed variant, which change whenever the
// cones do, take the budget at which the spread lies well inside it.
TEST(GeometryAwareUnbiased, FullMixConvergesToBdptOnTheDoorScene) {
  const auto scene = shipped_scene("door-ajar", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  MltStatistics stats;
  const Image image = mlt_image(*scene, kGamltMix, 8000, &stats);
  // A guard that the geometry-aware perturbations take a real part of the moves (they are
  // 4/9 of the proposals): their accepted moves are 19 % of all proposals here (since the
  // cube shapes took Mitsuba's triangulation; above 20 % before), nowhere near 0 as when
  // they never apply.
  EXPECT_GT(share_of(stats, "ga-lens") + share_of(stats, "ga-caustic"), 0.15);
  // 16 x 16 door scene: plain MLT at 4000 (the last test) is off by 11 % in its worst
  // quadrant and 3.8 % in total (the bootstrap's b), so the tolerance is 15 %.
  expect_converged_to(image, reference, 2, 0.15, 0.05);
}

// The same with delayed (two-stage) acceptance (--gamlt-acceptance delayed).
TEST(GeometryAwareUnbiased, FullMixWithDelayedAcceptanceConvergesToBdptOnTheDoorScene) {
  const auto scene = shipped_scene("door-ajar", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  MltStatistics stats;
  const Image image = mlt_image(*scene, kGamltMix, 8000, &stats, {.delayed_acceptance = true});
  EXPECT_GT(share_of(stats, "ga-lens") + share_of(stats, "ga-caustic"), 0.15);
  expect_converged_to(image, reference, 2, 0.15, 0.05);
}

// The same with the cheap conservative cones (--gamlt-cone field): narrower cones, smaller
// steps, the same target.
TEST(GeometryAwareUnbiased, FullMixWithTheFieldConesConvergesToBdptOnTheDoorScene) {
  const auto scene = shipped_scene("door-ajar", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  MltStatistics stats;
  const Image image = mlt_image(*scene, kGamltMix, 4000, &stats, {.field_cone = true});
  EXPECT_GT(share_of(stats, "ga-lens") + share_of(stats, "ga-caustic"), 0.15);
  expect_converged_to(image, reference, 2, 0.15, 0.05);
}

// The same with the exact walk for every segment (--gamlt-cone exact).
TEST(GeometryAwareUnbiased, FullMixWithTheExactConesConvergesToBdptOnTheDoorScene) {
  const auto scene = shipped_scene("door-ajar", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  MltStatistics stats;
  const Image image = mlt_image(*scene, kGamltMix, 4000, &stats, {.cone_cells = 0.0});
  EXPECT_GT(share_of(stats, "ga-lens") + share_of(stats, "ga-caustic"), 0.15);
  expect_converged_to(image, reference, 2, 0.15, 0.05);
}

// The same budget with plain MLT's mix, for the noise level of this scene at this size.
TEST(GeometryAwareUnbiased, PlainMixOnTheDoorSceneForComparison) {
  const auto scene = shipped_scene("door-ajar", 16);
  const Image reference = bdpt_reference(*scene, 4096);
  const Image image = mlt_image(*scene, kMltMix, 4000);
  expect_converged_to(image, reference, 2, 0.15, 0.05);
}

}  // namespace
