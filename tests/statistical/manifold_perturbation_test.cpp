// The manifold perturbation (mutations/manifold_perturbation.*) and its walk
// (mutations/manifold/specular_chain.*):
//  1. the walk's derivatives against finite differences of the traced chain through the
//     glass sphere (curved, refracting), and its Newton solution;
//  2. the proposal density: a histogram of where the moved vertex lands against the ratio
//     the code reports, through a mirror, where the chain's generalized geometry term is
//     known in closed form (the mirror image of the fixed end);
//  3. unbiasedness: MLT with the perturbation at high weight converges to BDPT on the glass
//     sphere and the caustic pool, and the injected bugs (the generalized geometry term
//     dropped; unconverged walks accepted) are caught.
// Offset manifolds (rough vertices crossed as specular): manifold_offset_test.cpp.
#include "mutations/manifold_perturbation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/mcmc/strategy_mix.h"
#include "emlt/scene/materials.h"
#include "mutations/bidirectional.h"
#include "mutations/manifold/specular_chain.h"
#include "mutations/perturbation_common.h"
#include "support/mlt_test_helpers.h"
#include "support/test_scenes.h"
#include "support/test_support.h"
#include "statistical/manifold_test_scenes.h"

using namespace emlt;
using namespace emlt::test;

namespace {

using Move = ManifoldPerturbation::Move;

// The first move of x whose chain between x_b and x_c has Dirac links (a manifold walk).
std::optional<Move> walking_move(const Path& x) {
  for (const Move& m : ManifoldPerturbation::moves(x))
    if (std::abs(m.c - m.b) > 1) return m;
  return std::nullopt;
}

manifold::ChainProblem chain_problem(const Scene& scene, const Path& x, const Move& m) {
  const auto& v = x.vertices;
  manifold::ChainProblem problem;
  problem.scene = &scene;
  problem.start = v[size_t(m.c)];
  problem.mode = m.step > 0 ? TransportMode::Radiance : TransportMode::Importance;
  for (int i = m.c - m.step; i != m.b; i -= m.step)
    problem.links.push_back(
        {v[size_t(i)].bsdf,
         perturbation::crosses_surface(v[size_t(i)], v[size_t(i + 1)], v[size_t(i - 1)])});
  problem.target = DVec3(v[size_t(m.b)].position);
  problem.target_normal = DVec3(v[size_t(m.b)].normal);
  return problem;
}

std::vector<std::pair<Path, Move>> walking_paths(const Scene& scene, int count) {
  std::vector<std::pair<Path, Move>> found;
  for (const Path& x : bootstrap_paths(scene, 4000, 8)) {
    const auto m = walking_move(x);
    if (m) found.emplace_back(x, *m);
    if (int(found.size()) == count) break;
  }
  return found;
}

// ---------------------------------------------------------------------------------------
// 1. The walk.

TEST(ManifoldWalk, DerivativesMatchFiniteDifferencesThroughTheGlassSphere) {
  const auto scene = shipped_scene("cornell-glass", 32);
  const auto paths = walking_paths(*scene, 40);
  ASSERT_GE(paths.size(), 20u);
  int refracting = 0, checked = 0;
  double worst = 0.0;
  for (const auto& [x, m] : paths) {
    const auto problem = chain_problem(*scene, x, m);
    const DVec3 w =
        perturbation::precise_direction(x.vertices[size_t(m.c)], x.vertices[size_t(m.c - m.step)]);
    manifold::ChainTrace at;
    if (!manifold::trace_chain(problem, w, &at)) continue;
    // The chain as the path has it: the trace ends where x_b is.
    const double length = glm::length(DVec3(x.vertices[size_t(m.c)].position) - problem.target);
    EXPECT_LT(at.residual, 1e-3 * length);
    for (const auto& link : problem.links) refracting += link.transmission;
    // Central differences of the end point, turning ω about the same axes.
    const DVec3 helper = std::abs(w.x) < 0.9 ? DVec3(1, 0, 0) : DVec3(0, 1, 0);
    const DVec3 s = glm::normalize(glm::cross(helper, w)), t = glm::cross(w, s);
    // A step small against the map's curvature where the chain magnifies turns strongly
    // (grazing reflections), large against the float hits' noise elsewhere.
    const double magnification =
        std::max({std::abs(at.jacobian[0][0]), std::abs(at.jacobian[0][1]),
                  std::abs(at.jacobian[1][0]), std::abs(at.jacobian[1][1])});
    const double h = 2e-4 * std::min(1.0, 500.0 / magnification);
    bool ok = true;
    double column[2][2];
    for (int j = 0; j < 2; ++j) {
      const DVec3 axis = j == 0 ? s : t;
      manifold::ChainTrace plus, minus;
      if (!manifold::trace_chain(problem, w + h * axis, &plus) ||
          !manifold::trace_chain(problem, w - h * axis, &minus)) {
        ok = false;
        break;
      }
      for (int r = 0; r < 2; ++r) column[r][j] = (plus.offset[r] - minus.offset[r]) / (2.0 * h);
    }
    if (!ok) continue;
    const double scale = std::max({std::abs(at.jacobian[0][0]), std::abs(at.jacobian[0][1]),
                                   std::abs(at.jacobian[1][0]), std::abs(at.jacobian[1][1])});
    for (int r = 0; r < 2; ++r)
      for (int j = 0; j < 2; ++j)
        worst = std::max(worst, std::abs(column[r][j] - at.jacobian[r][j]) / scale);
    ++checked;
  }
  std::printf(
      "[ info     ] %d chains (%d refractions): worst Jacobian entry off by %.2e of the largest\n",
      checked, refracting, worst);
  EXPECT_GE(checked, 15);
  EXPECT_GT(refracting, 10);
  EXPECT_LT(worst, 0.01);
}

TEST(ManifoldWalk, NewtonFindsTheChainToAMovedEndAndBack) {
  const auto scene = shipped_scene("cornell-glass", 32);
  int solved = 0, tried = 0;
  for (const auto& [x, m] : walking_paths(*scene, 30)) {
    auto problem = chain_problem(*scene, x, m);
    const DVec3 original = problem.target;
    const DVec3 guess =
        perturbation::precise_direction(x.vertices[size_t(m.c)], x.vertices[size_t(m.c - m.step)]);
    // Move the target a little within its plane.
    DVec3 tangent = glm::cross(problem.target_normal, DVec3(0.3, 0.8, 0.5));
    tangent = glm::normalize(tangent);
    const double length = glm::length(DVec3(x.vertices[size_t(m.c)].position) - original);
    problem.target = original + 0.003 * length * tangent;
    ++tried;
    const auto moved = manifold::solve_chain(problem, guess, 1e-5 * length);
    if (!moved) continue;
    EXPECT_LT(moved->residual, 1e-5 * length);
    problem.target = original;
    const auto back = manifold::solve_chain(problem, moved->direction, 1e-5 * length);
    ASSERT_TRUE(back.has_value());
    for (size_t j = 0; j < back->links.size(); ++j) {
      const int i = m.c - m.step * int(j + 1);
      EXPECT_LT(glm::length(DVec3(back->links[j].position) - DVec3(x.vertices[size_t(i)].position)),
                1e-3 * length);
    }
    ++solved;
  }
  std::printf("[ info     ] %d of %d walks converged\n", solved, tried);
  EXPECT_GE(solved, tried * 8 / 10);
}

TEST(ManifoldPerturbation, VonMisesFisherPeakAndNormalisation) {
  for (const double peak : {0.2, 1.0, 30.0, 5000.0}) {
    const double kappa = ManifoldPerturbation::concentration_for_peak(peak);
    EXPECT_NEAR(std::exp(ManifoldPerturbation::log_vmf_density(kappa, 1.0)) / peak, 1.0, 1e-9);
    // ∫ p dω = 2π ∫ p(cos θ) d cos θ = 1, by the midpoint rule in 1 - cos θ over the lobe
    // (beyond 60/κ it holds less than e^-60).
    const int n = 200000;
    const double span = std::min(2.0, 60.0 / kappa);
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
      sum += std::exp(ManifoldPerturbation::log_vmf_density(kappa, 1.0 - span * (i + 0.5) / n));
    EXPECT_NEAR(sum * 2.0 * M_PI * span / n, 1.0, 1e-4) << "peak " << peak;
  }
  EXPECT_EQ(ManifoldPerturbation::concentration_for_peak(1.0 / (4.0 * M_PI)), 0.0);
}

// ---------------------------------------------------------------------------------------
// 2. The proposal density through a mirror: the floor point x3 seen from the lens moves,
// the mirror point x2 is re-solved so that the chain still reaches the fixed lit floor
// point x1.

TEST(ManifoldPerturbationDensity, RatioThroughAMirrorMatchesTheHistogramOfLandingPoints) {
  const auto scene = Scene::build(test::floor_mirror_description());
  MutationContext ctx{*scene};
  ctx.manifold_prob_factor = 8.0;  // a wide lobe: the histograms need hits
  SurfaceHit seen;
  const Vec2 raster(16.5f, 16.5f);
  ASSERT_TRUE(scene->intersect(scene->camera().generate_ray(raster, Vec2(0.5f)), seen));
  const Path x = test::floor_mirror_light_path(
      *scene, raster, glm::normalize(Vec3(0.0f, 1.0f, 1.5f) - seen.position));
  ASSERT_EQ(x.type.to_string(), "L D S D E");
  const Move move{4, 3, 1, -1};
  bool listed = false;
  for (const Move& m : ManifoldPerturbation::moves(x))
    listed |= m.a == move.a && m.b == move.b && m.c == move.c && m.step == move.step;
  ASSERT_TRUE(listed);

  const ManifoldPerturbation manifold, without_term(ManifoldPerturbation::Faults{true, false});
  // y: the lens direction turned by about a pixel's angle, the seen point moving away from
  // the light (a move towards it soon finds the light's quad between floor and mirror).
  const Vec3 x_direction = direction_between(x.vertices[4], x.vertices[3]);
  const Vec3 axis = glm::normalize(glm::cross(x_direction, Vec3(1, 0, 0)));
  const float angle = -0.04f;
  const Vec3 y_direction = glm::normalize(x_direction * std::cos(angle) + axis * std::sin(angle));
  const auto y = manifold.perturb_to(x, move, y_direction, ctx);
  ASSERT_TRUE(y.has_value());
  const Path& yp = y->path;
  ASSERT_EQ(yp.type.to_string(), "L D S D E");
  EXPECT_EQ(yp.vertices[1].position, x.vertices[1].position) << "x_c stays";

  const auto landing = [&](const Path& from, const Path& to, uint64_t seed) {
    Rng rng(seed, 7);
    const int proposals = 800000;
    const float radius = 0.03f;
    int hits = 0;
    for (int i = 0; i < proposals; ++i) {
      const auto direction =
          ManifoldPerturbation::sample_direction(from, move, ctx, rng.uniform2());
      if (!direction) continue;
      const auto p = manifold.perturb_to(from, move, *direction, ctx);
      if (p && glm::length(p->path.vertices[3].position - to.vertices[3].position) < radius) ++hits;
    }
    EXPECT_GT(hits, 800) << "too few landings for a density estimate";
    return double(hits) / (double(proposals) * kPi * radius * radius);
  };
  const double measured = landing(x, yp, 11) / landing(yp, x, 12);  // over the seen point's area
  // The reported ratio is over ν; x3's area differs from it by the chain's factor.
  const double to_area = std::exp(test::log_floor_area_per_nu(x) - test::log_floor_area_per_nu(yp));
  const double reported = std::exp(-y->log_reverse_over_forward) * to_area;
  std::printf("[ info     ] T(x->y)/T(y->x): histogram %.4f, reported %.4f (nu->area %.4f)\n",
              measured, reported, to_area);
  EXPECT_NEAR(measured / reported, 1.0, 0.06);

  const auto wrong = without_term.perturb_to(x, move, y_direction, ctx);
  ASSERT_TRUE(wrong.has_value());
  const double reported_wrong = std::exp(-wrong->log_reverse_over_forward) * to_area;
  std::printf("[ info     ] without the generalized geometry term: reported %.4f\n",
              reported_wrong);
  EXPECT_GT(std::abs(measured / reported_wrong - 1.0), 0.12);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// 3. Unbiasedness.

std::shared_ptr<const StrategyMix> manifold_mix(ManifoldPerturbation::Faults faults,
                                                double weight) {
  auto mix = std::make_shared<StrategyMix>(StrategyMix::parse("bidir=1"));
  mix->add("manifold", std::make_unique<ManifoldPerturbation>(faults), weight);
  return mix;
}

Image manifold_image(const Scene& scene, ManifoldPerturbation::Faults faults, double mpp,
                     MltStatistics* stats = nullptr) {
  RenderSettings s = base_settings();
  s.mutations_per_pixel = mpp;
  s.chains = 256;
  s.bootstrap_samples = 50000;
  s.direct_spp = 256;
  MltOptions options;
  options.mix = manifold_mix(faults, 4.0);
  const MltIntegrator mlt(options);
  Image image = render(mlt, scene, s);
  if (stats) *stats = mlt.statistics();
  return image;
}

// A glass ball above a floor under a small light, seen from above: the image is mostly the
// ball's caustic (L S S D E), whose brightness across the floor is the chain's generalized
// geometry term itself, and the floor seen through the ball (L D S S E).
std::unique_ptr<Scene> caustic_under_a_ball(BsdfPtr ball_material) {
  SceneDescription d;
  d.source = "caustic-under-a-ball";
  const int white = test::add_material(d, make_lambertian(Rgb(0.6f)));
  const int glass = test::add_material(d, std::move(ball_material));
  test::add_quad(d, {-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, white, Rgb(0.0f));  // faces +y
  const float h = 3.0f, r = 0.15f;
  test::add_quad(d, {-r, h, -r}, {r, h, -r}, {r, h, r}, {-r, h, r}, white,
                 Rgb(400.0f));  // faces -y
  SphereDesc ball;
  ball.center = Vec3(0.0f, 0.9f, 0.0f);
  ball.radius = 0.5f;
  ball.material = glass;
  d.spheres.push_back(ball);
  d.camera = test::camera_at(Vec3(0.0f, 2.6f, -1.2f), Vec3(0.0f, 0.0f, 0.25f), 16);
  return Scene::build(std::move(d));
}

// MLT with bidir=1,manifold=4 against BDPT: the image total within `total` and each
// quadrant within `quadrant`, the manifold perturbation carrying at least `share` of the
// accepted moves.
void expect_manifold_mix_converges(const Scene& scene, int reference_spp, double mpp, double share,
                                   double quadrant, double total) {
  const Image reference = bdpt_reference(scene, reference_spp);
  MltStatistics stats;
  const Image image = manifold_image(scene, {}, mpp, &stats);
  EXPECT_GT(share_of(stats, "manifold"), share);
  expect_converged_to(image, reference, 2, quadrant, total);
}

// The same noise as the caustic perturbation's tests (perturbation_test.cpp); the sharp
// checks are the density and derivative tests above.
TEST(ManifoldPerturbationUnbiased, ConvergesToBdptOnTheGlassSphere) {
  expect_manifold_mix_converges(*shipped_scene("cornell-glass", 16), 2048, 3000, 0.3, 0.12, 0.05);
}

TEST(ManifoldPerturbationUnbiased, ConvergesToBdptOnACausticUnderAGlassBall) {
  expect_manifold_mix_converges(*caustic_under_a_ball(), 4096, 2000, 0.2, 0.1, 0.04);
}

TEST(ManifoldPerturbationUnbiased, ConvergesToBdptOnTheCausticPool) {
  expect_manifold_mix_converges(*shipped_scene("caustic-pool", 16), 2048, 2000, 0.2, 0.12, 0.05);
}

// Every proposal's chain must lie on the specular manifold: at each Dirac link, the lobe
// turns the direction from one neighbour into the direction to the other. A walk that did
// not converge leaves its last link pointing past x_b.
TEST(ManifoldPerturbation, ProposedChainsAreSpecularAndUnconvergedWalksAreCaught) {
  const auto scene = shipped_scene("cornell-glass", 32);
  MutationContext ctx{*scene};
  ctx.manifold_prob_factor = 3.0;  // wide steps: many walks fail to converge
  const auto count_bent = [&](const ManifoldPerturbation& mutation, int* proposed) {
    int bent = 0;
    Rng rng(5, 3);
    for (const auto& [x, m] : walking_paths(*scene, 60)) {
      for (int n = 0; n < 40; ++n) {
        const auto direction = ManifoldPerturbation::sample_direction(x, m, ctx, rng.uniform2());
        if (!direction) continue;
        const auto y = mutation.perturb_to(x, m, *direction, ctx);
        if (!y) continue;
        ++*proposed;
        const auto& v = y->path.vertices;
        for (int i = std::min(m.b, m.c) + 1; i < std::max(m.b, m.c); ++i) {
          const bool transmission =
              perturbation::crosses_surface(v[size_t(i)], v[size_t(i + 1)], v[size_t(i - 1)]);
          const auto out = perturbation::continue_through_delta(
              v[size_t(i)], direction_between(v[size_t(i)], v[size_t(i + 1)]),
              TransportMode::Radiance, transmission);
          const DVec3 to_light = perturbation::precise_direction(v[size_t(i)], v[size_t(i - 1)]);
          if (!out || perturbation::angle_between(DVec3(*out), to_light) > 1e-3) {
            ++bent;
            break;
          }
        }
      }
    }
    return bent;
  };
  int proposed = 0, proposed_with_bug = 0;
  const int bent = count_bent(ManifoldPerturbation(), &proposed);
  const int bent_with_bug = count_bent(ManifoldPerturbation({false, true}), &proposed_with_bug);
  std::printf(
      "[ info     ] bent chains: %d of %d proposals; accepting unconverged walks: %d of %d\n", bent,
      proposed, bent_with_bug, proposed_with_bug);
  EXPECT_GT(proposed, 500);
  EXPECT_LE(bent, proposed / 500);
  EXPECT_GT(bent_with_bug, bent + 20);
}
