// The anisotropic path perturbation's two-vertex density ratio on real geometry: the Cornell
// box's L D D E paths, where x_c is the emitter vertex and both x_a and x_b move.
//
// Target: uniform in area measure over the paths whose x_a lies within R of a fixed point
// on its face and x_b within R of a fixed point on its face, with f > 0 (so occlusion,
// the film's edge and the light's facing cut the two discs). An exact draw of it comes
// from rejection sampling: uniform points in the two discs, kept where they form such a
// path. Each chain starts from an exact draw and takes a few Metropolis-Hastings steps
// with the strategy alone (a proposal outside the region has target 0); under detailed
// balance its final state is again an exact draw, so the final states of independent
// chains, binned in rings of r_a² and r_b², match the target's cell probabilities (from a
// large independent draw) by a chi-square test. The reverse move's Σ evaluated at x, or the
// reverse density dropped, makes the chains drift (within a face those two bugs coincide).
// The test was written to find the bias of the degenerate casts (anisotropic_path.h); it
// showed both orders right within faces, which pointed at the moves between faces.
// Moves that leave a face cannot be tested this way; emlt_test.cpp covers them by
// rendering.
#include "mutations/ensemble/anisotropic_path.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

#include "emlt/core/frame.h"
#include "emlt/mcmc/ensemble_guides.h"
#include "emlt/path/connection.h"
#include "mutations/perturbation_common.h"
#include "support/mlt_test_helpers.h"
#include "support/test_support.h"

namespace emlt {
namespace {

constexpr int kImageSize = 16;
constexpr float kRadius = 60.0f;  // scene units (the box is 556 wide)
constexpr int kRings = 5;         // per vertex, equal-area rings of the disc
constexpr int kChains = 10000;
constexpr int kSteps = 100;

struct Region {
  Path centre;  // x_c = x_0 on the light, x_b = x_1, x_a = x_2, the lens x_3
  Vec3 centre_a{0.0f}, centre_b{0.0f}, normal_a{0.0f}, normal_b{0.0f};

  explicit Region(const Path& path) : centre(path) {
    centre_a = path.vertices[2].position;
    centre_b = path.vertices[1].position;
    normal_a = path.vertices[2].normal;
    normal_b = path.vertices[1].normal;
  }
  static bool on_face(const PathVertex& v, const Vec3& centre, const Vec3& normal) {
    return glm::dot(v.normal, normal) > 0.999f &&
           std::abs(glm::dot(v.position - centre, normal)) < 0.05f &&
           glm::length(v.position - centre) < kRadius;
  }
  // The target's support (up to f > 0, checked by the callers).
  bool contains(const Path& y) const {
    return on_face(y.vertices[2], centre_a, normal_a) && on_face(y.vertices[1], centre_b, normal_b);
  }
  int cell(const Path& y) const {
    const auto ring = [](const Vec3& p, const Vec3& c) {
      const float r = glm::length(p - c) / kRadius;
      return std::min(kRings - 1, int(r * r * float(kRings)));
    };
    return ring(y.vertices[2].position, centre_a) * kRings + ring(y.vertices[1].position, centre_b);
  }
};

bool has_light(const Scene& scene, const Path& y) {
  return !is_black(connect_vertices(scene, nullptr, y.vertices[0], y.vertices[1], &y.vertices[2]));
}

// One exact draw of the target, or nothing (the pair of disc points was rejected).
std::optional<Path> draw(const Scene& scene, const Region& region, Rng& rng) {
  const Frame frame_a(region.normal_a), frame_b(region.normal_b);
  const auto disc_point = [&](const Vec3& centre, const Frame& frame) {
    const double r = kRadius * std::sqrt(rng.uniform_double()),
                 phi = 2.0 * kPi * rng.uniform_double();
    return centre + float(r * std::cos(phi)) * frame.s + float(r * std::sin(phi)) * frame.t;
  };
  const Vec3 a = disc_point(region.centre_a, frame_a), b = disc_point(region.centre_b, frame_b);
  const Vec3 lens = region.centre.vertices[3].position;
  const auto raster = scene.camera().raster_position(lens, glm::normalize(a - lens));
  if (!raster) return std::nullopt;
  // Rays reach the points only within rounding (grazing views): 0.5 units is far below the
  // rings' widths and far above the hits' errors.
  const auto hit_a =
      perturbation::trace_surface(scene, Ray{lens, glm::normalize(a - lens), 0.0f, kInfinity});
  if (!hit_a || glm::length(hit_a->position - a) > 0.5f) return std::nullopt;
  const auto hit_b = perturbation::trace_surface(
      scene, spawn_ray(hit_a->position, hit_a->normal, glm::normalize(b - hit_a->position)));
  if (!hit_b || glm::length(hit_b->position - b) > 0.5f) return std::nullopt;
  Path y = region.centre;
  y.vertices[2] = *hit_a;
  y.vertices[1] = *hit_b;
  y.vertices[3].raster = *raster;
  if (!region.contains(y) || !has_light(scene, y)) return std::nullopt;
  if (!perturbation::finish_proposal(scene, region.centre, y)) return std::nullopt;
  if (!(path_luminance(scene, y) > 0.0)) return std::nullopt;
  return y;
}

struct Fixture {
  std::unique_ptr<Scene> scene = test::shipped_scene("cornell-box", kImageSize);
  std::vector<Path> paths = test::bootstrap_paths(*scene, 400, 3);
  EnsembleGuides ensemble;
  Fixture() {
    std::vector<const Path*> pointers;
    for (const Path& p : paths) pointers.push_back(&p);
    // M = 32 guides: the fitted Σ then varies enough over the region that the dropped reverse
    // density shows within a face (with the default 8, p = 0.53 in that test).
    EnsembleParams params;
    params.neighbours = 32;
    ensemble.build(pointers, kImageSize, kImageSize, 3, params);
  }
  // The first L D D E path of the bootstrap whose x_b satisfies `where`.
  const Path* find(const std::function<bool(const PathVertex&)>& where) const {
    for (const Path& p : paths)
      if (p.edges() == 3 && where(p.vertices[1])) return &p;
    return nullptr;
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

struct Outcome {
  test::ChiSquareResult chi_square;
  double acceptance = 0.0;
};

// The target's probability of each cell, from a large independent draw.
std::vector<double> cell_probabilities(const Region& region) {
  std::vector<double> counts(kRings * kRings, 0.0);
  Rng rng(17, 0);
  for (int i = 0; i < 400000; ++i)
    if (const auto y = draw(*fixture().scene, region, rng)) counts[size_t(region.cell(*y))] += 1.0;
  double total = 0.0;
  for (double c : counts) total += c;
  EXPECT_GT(total, 50000.0) << "the region should hold plenty of paths";
  for (double& c : counts) c /= total;
  return counts;
}

Outcome run(const Region& region, const std::vector<double>& probabilities,
            double toward_camera_probability, ensemble::InjectedBugs bugs = {}, int steps = kSteps,
            AnisotropicPathParams params = {}) {
  const Fixture& f = fixture();
  const Scene& scene = *f.scene;
  params.toward_camera_probability = toward_camera_probability;
  const AnisotropicPathPerturbation strategy(params, bugs);
  MutationContext ctx{scene};
  ctx.ensemble = &f.ensemble;
  ctx.min_edges = ctx.max_edges = 3;

  std::vector<double> observed(kRings * kRings, 0.0);

  double accepted = 0.0;
  for (int c = 0; c < kChains; ++c) {
    Rng rng(31, uint64_t(c));
    std::optional<Path> x;
    while (!x) x = draw(scene, region, rng);
    ctx.chain = uint64_t(c);
    for (int s = 0; s < steps; ++s) {
      ctx.step = uint64_t(s);
      const auto y = strategy.propose(*x, rng, ctx);
      if (!y || !region.contains(y->path) || !(path_luminance(scene, y->path) > 0.0)) continue;
      if (rng.uniform_double() < std::exp(std::min(0.0, y->log_reverse_over_forward))) {
        *x = y->path;
        accepted += 1.0;
      }
    }
    observed[size_t(region.cell(*x))] += 1.0;
  }
  std::vector<double> expected(probabilities);
  for (double& e : expected) e *= double(kChains);
  Outcome outcome;
  outcome.chi_square = test::chi_square_test(observed, expected);
  outcome.acceptance = accepted / (double(kChains) * double(steps));
  std::printf("[ info     ] toward %.1f: chi2 %.1f (%d dof) p = %.3g, acceptance %.3f\n",
              toward_camera_probability, outcome.chi_square.statistic,
              outcome.chi_square.degrees_of_freedom, outcome.chi_square.p_value,
              outcome.acceptance);
  return outcome;
}

bool on_floor(const PathVertex& v) {
  return v.normal.y > 0.999f && std::abs(v.position.y) < 1e-3f;
}
bool on_tall_block_top(const PathVertex& v) {
  return v.normal.y > 0.999f && std::abs(v.position.y - 330.0f) < 1e-3f;
}

TEST(AnisotropicPathDensity, KeepsAUniformTargetInBothOrders) {
  for (const auto& where : {on_floor, on_tall_block_top}) {
    const Path* path = fixture().find(where);
    ASSERT_NE(path, nullptr);
    const Region region(*path);
    const auto probabilities = cell_probabilities(region);
    for (const double toward : {0.0, 1.0}) {
      SCOPED_TRACE(toward > 0.0 ? "toward the camera" : "from the camera");
      const Outcome outcome = run(region, probabilities, toward);
      EXPECT_GT(outcome.chi_square.p_value, 1e-3);
      EXPECT_GT(outcome.acceptance, 0.1) << "chains that never move pass any test";
    }
  }
}

// Every fit falls back: the world-space vertices move by the paper's vMF about the
// direction from the cast origin, the image point by the isotropic Gaussian.
TEST(AnisotropicPathDensity, KeepsAUniformTargetWithEveryFitFallingBack) {
  AnisotropicPathParams params;
  params.min_effective_guides = std::numeric_limits<double>::infinity();
  // Wider than the default vMF and narrower than the default image Gaussian (2 px is an
  // eighth of this 16-pixel image): moves of about 10 units, which cross the 60-unit region.
  params.fallback_concentration = 2e3;
  params.image_fallback_sigma = 0.25;
  const Region region(*fixture().find(on_floor));
  const auto probabilities = cell_probabilities(region);
  for (const double toward : {0.0, 1.0}) {
    SCOPED_TRACE(toward > 0.0 ? "toward the camera" : "from the camera");
    const Outcome outcome = run(region, probabilities, toward, {}, kSteps, params);
    EXPECT_GT(outcome.chi_square.p_value, 1e-3);
    EXPECT_GT(outcome.acceptance, 0.1) << "chains that never move pass any test";
  }
}

TEST(AnisotropicPathDensity, DroppedReverseDensityIsDetected) {
  // Toward the camera both vertices are ray-cast, so the reverse density differs from the
  // forward one even within a face; the drift is slow, so these chains run 4x longer. It
  // shows fastest with the isotropic-Gaussian fallback option (the paper's alternative to
  // the vMF): measured p = 4.6e-6 (1.1e-3 after the usual 100 steps). With the default vMF
  // fallback p = 0.016, and with every fit used p = 0.34: within a face those kernels are
  // nearly symmetric, so the bug drifts too slowly for this test; the renders in
  // emlt_test.cpp catch it in both orders. Within a face Σ evaluated at x gives the same
  // chains. From the camera the world step is symmetric within a face and the image step
  // nearly so (p ~ 4e-4 even at 100 steps): that order's bugs, and the moves between faces,
  // are caught by rendering too.
  ensemble::InjectedBugs reverse;
  reverse.drop_reverse_density = true;
  const Region region(*fixture().find(on_floor));
  AnisotropicPathParams gaussian_fallback;
  gaussian_fallback.fallback_concentration = 0.0;
  EXPECT_LT(run(region, cell_probabilities(region), 1.0, reverse, 4 * kSteps, gaussian_fallback)
                .chi_square.p_value,
            1e-4);
}

}  // namespace
}  // namespace emlt
