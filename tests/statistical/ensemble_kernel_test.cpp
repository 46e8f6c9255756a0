// The guided kernels of Ensemble MLT (mutations/ensemble/), tested without rendering as in
// design notes section 6: a complementary set of guides is drawn once from a known target
// pi and frozen; each kernel alone drives Metropolis-Hastings chains on pi with
//     a = min(1, pi(y)/pi(x) * exp(log T(y->x) - log T(x->y)) * P(n|y)/P(n|x)).
// Every chain starts from an exact draw of pi, so if the kernel satisfies detailed balance
// w.r.t. pi the state after any number of steps is again an exact draw of pi, and the final
// states of independent chains are i.i.d.: a chi-square test of their histogram against
// pi's cell probabilities is exact. A wrong ratio makes the chains drift toward a different
// stationary law, which the same test detects; each injected bug must give p < 1e-6.
// Because a chain that never moves would also pass, every passing run must show a healthy
// acceptance rate and most chains leaving their starting state.
//
// Targets: a 3-component 2-D Gaussian mixture (linear, anisotropic kernels; cells of a
// grid plus one "outside" cell, probabilities by Simpson integration) and a 3-lobe vMF
// mixture on S^2 (great-arc and directional kernels; equal-area (cos theta, phi) cells).
// Cells whose probability is below 1e-3 are pooled (chi_square_test's min_expected).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "statistical/ensemble_kernel_harness.h"

using namespace emlt;
using namespace emlt::ensemble;
using namespace emlt::ensemble_test;

namespace {
// Chains per run and MH steps per chain: enough for every injected bug to give p ~ 0.
constexpr int kChains = 20000;
constexpr int kSteps = 24;

// Bugs injected by the test kernels below (never by the library).
enum class Injected {
  None,
  DroppedReverseDensity,  // log ratio forced to 0
  WrongJacobian,          // linear: lambda^1 whatever g; great arc: the paper's eq. 10 as printed
  IgnoredSelection,       // P(n|y)/P(n|x) left out
  SigmaNotRefitted,       // anisotropic: reverse density under the forward Sigma(x)
  FallbackNotRedecided,   // anisotropic: reverse copies the forward fallback decision
  MixtureAsGaussian,      // anisotropic scale mixture: densities of the single Gaussian
};

// ---------------------------------------------------------------------------------------
// Linear kernel in R^2 with similarity-weighted guide choice.

struct LinearTestKernel {
  std::vector<Vec2> guides;
  StretchParams stretch;
  SimilarityParams similarity{kPaperSimilarityEpsilon, 0.5};
  Injected bug = Injected::None;
  std::vector<double> log_weights_x, log_weights_y;

  Step<Vec2> operator()(const Vec2& x, Rng& rng) {
    log_weights_x.resize(guides.size());
    log_weights_y.resize(guides.size());
    log_similarities_to_guides(x, guides, similarity, log_weights_x);
    const GuideChoice choice = choose_guide(log_weights_x, rng);
    const LinearProposal proposal = propose_linear(x, guides[choice.index], stretch, rng);
    if (!proposal.valid) return {x, 0.0, false};
    double log_ratio = proposal.log_density_ratio;
    if (bug == Injected::DroppedReverseDensity) log_ratio = 0.0;
    if (bug == Injected::WrongJacobian) log_ratio = std::log(proposal.lambda);
    if (bug != Injected::IgnoredSelection) {
      log_similarities_to_guides(proposal.state, guides, similarity, log_weights_y);
      log_ratio += guide_log_probability(log_weights_y, choice.index) - choice.log_probability;
    }
    return {proposal.state, log_ratio, true};
  }
};

ChainReport run_linear(const char* label, StretchDistribution distribution, double alpha,
                       Injected bug) {
  const PlaneMixture target = plane_target();
  const PlaneGrid grid;
  LinearTestKernel kernel;
  kernel.guides = frozen_guides<Vec2>(target, 24, 1);
  kernel.stretch = {alpha, distribution};
  kernel.bug = bug;
  const auto probabilities =
      grid.probabilities([&](double x, double y) { return target.density(x, y); });
  return run_chains<Vec2>(
      label, target, kernel, [&](const Vec2& p) { return grid.cell_of(p.x, p.y); }, probabilities,
      kChains, kSteps);
}

// ---------------------------------------------------------------------------------------
// Great-arc kernel on S^2 with similarity-weighted guide choice.

struct GreatArcTestKernel {
  std::vector<Vec3> guides;
  StretchParams stretch{1.0, StretchDistribution::InverseSqrt};
  SimilarityParams similarity{kPaperSimilarityEpsilon, 0.5};
  Injected bug = Injected::None;
  std::vector<double> log_weights_x, log_weights_y;

  Step<Vec3> operator()(const Vec3& x, Rng& rng) {
    log_weights_x.resize(guides.size());
    log_weights_y.resize(guides.size());
    log_similarities_to_guides(x, guides, similarity, log_weights_x);
    const GuideChoice choice = choose_guide(log_weights_x, rng);
    const GreatArcProposal proposal = propose_great_arc(x, guides[choice.index], stretch, rng);
    if (!proposal.valid) return {x, 0.0, false};
    double log_ratio = proposal.log_density_ratio;
    if (bug == Injected::DroppedReverseDensity) log_ratio = 0.0;
    if (bug == Injected::WrongJacobian)  // eq. 10 as printed: sin W / sin(lambda W)
      log_ratio =
          std::log(std::sin(proposal.angle_current)) - std::log(std::sin(proposal.angle_proposed));
    if (bug != Injected::IgnoredSelection) {
      log_similarities_to_guides(proposal.direction, guides, similarity, log_weights_y);
      log_ratio += guide_log_probability(log_weights_y, choice.index) - choice.log_probability;
    }
    return {proposal.direction, log_ratio, true};
  }
};

ChainReport run_great_arc(const char* label, Injected bug) {
  const SphereMixture target = sphere_target();
  const SphereGrid grid;
  GreatArcTestKernel kernel;
  kernel.guides = frozen_guides<Vec3>(target, 24, 2);
  kernel.bug = bug;
  return run_chains<Vec3>(
      label, target, kernel, [&](const Vec3& w) { return grid.cell_of(w); },
      grid.probabilities(target), kChains, kSteps);
}

// ---------------------------------------------------------------------------------------
// Anisotropic kernel on the plane z = 0 (the ray-cast is the identity).

const Vec3 kPlaneNormal(0.0f, 0.0f, 1.0f);

struct PlaneTargetIn3d {  // the 2-D mixture seen as points (x, y, 0)
  PlaneMixture mixture = plane_target();
  Vec3 sample(Rng& rng) const { return Vec3(mixture.sample(rng), 0.0f); }
  double log_density(const Vec3& p) const { return mixture.log_density(Vec2(p.x, p.y)); }
};

struct AnisotropicTestKernel {
  std::vector<Vec3> guides;
  AnisotropicParams params;
  Injected bug = Injected::None;

  Step<Vec3> operator()(const Vec3& x, Rng& rng) const {
    const GuideSet set{guides, {}};
    if (bug == Injected::None) {
      const AnisotropicProposal p = propose_anisotropic_on_plane(x, kPlaneNormal, set, params, rng);
      return {p.state, p.log_density_ratio(), true};
    }
    const TangentGaussian forward = fit_tangent_gaussian(x, kPlaneNormal, set, params);
    const Vec3 y = sample_tangent_gaussian(forward, rng);
    const double log_forward = tangent_gaussian_log_pdf(forward, y);
    double log_reverse = log_forward;         // DroppedReverseDensity
    if (bug == Injected::SigmaNotRefitted) {  // recentred at y, but Sigma(x) kept
      TangentGaussian stale = forward;
      stale.centre = glm::dvec3(y);
      log_reverse = tangent_gaussian_log_pdf(stale, x);
    }
    if (bug == Injected::MixtureAsGaussian) {  // sampled from the mixture, evaluated without
      TangentGaussian at_x = forward, at_y = fit_tangent_gaussian(y, kPlaneNormal, set, params);
      at_x.smallest_scale = at_y.smallest_scale = 1.0;
      return {y, tangent_gaussian_log_pdf(at_y, x) - tangent_gaussian_log_pdf(at_x, y), true};
    }
    if (bug == Injected::FallbackNotRedecided) {
      AnisotropicParams forced = params;  // force the forward branch at y
      forced.min_effective_guides = forward.fallback ? 1e300 : 0.0;
      forced.min_determinant = forward.fallback ? params.min_determinant : -1e300;
      log_reverse = tangent_gaussian_log_pdf(fit_tangent_gaussian(y, kPlaneNormal, set, forced), x);
    }
    return {y, log_reverse - log_forward, true};
  }
};

AnisotropicParams anisotropic_test_params() {
  AnisotropicParams params;
  params.similarity.length_scale = 0.3;
  params.covariance_scale = 0.5;
  params.floor_sigma = 0.02;
  params.fallback_sigma = 0.15;
  params.min_effective_guides = 3.0;
  return params;
}

// printed: eq. 11's covariance as printed (1/(M-1), normalised weights, no further factor).
// smallest_scale < 1: the kernel's scale mixture (--ensemble-aniso-multiscale).
ChainReport run_anisotropic(const char* label, Injected bug, bool printed = false,
                            double smallest_scale = 1.0) {
  const PlaneTargetIn3d target;
  const PlaneGrid grid;
  AnisotropicTestKernel kernel;
  kernel.guides = frozen_guides<Vec3>(target, 24, 3);
  kernel.params = anisotropic_test_params();
  if (printed) {
    kernel.params.printed_normalisation = true;
    kernel.params.covariance_scale = 1.0;
  }
  kernel.params.smallest_scale = smallest_scale;
  kernel.bug = bug;
  const auto probabilities =
      grid.probabilities([&](double x, double y) { return target.mixture.density(x, y); });
  return run_chains<Vec3>(
      label, target, kernel, [&](const Vec3& p) { return grid.cell_of(p.x, p.y); }, probabilities,
      kChains, kSteps);
}

// ---------------------------------------------------------------------------------------
// Directional kernel on S^2.

struct DirectionalTestKernel {
  std::vector<Vec3> guides;
  DirectionalParams params;
  Injected bug = Injected::None;

  Step<Vec3> operator()(const Vec3& x, Rng& rng) const {
    const DirectionalProposal p = propose_directional(x, GuideSet{guides, {}}, params, rng);
    return {p.direction, bug == Injected::DroppedReverseDensity ? 0.0 : p.log_density_ratio(),
            true};
  }
};

DirectionalParams directional_test_params() {
  DirectionalParams params;
  params.similarity.length_scale = 0.3;
  params.concentration_scale = 2.0;
  params.fallback_concentration = 50.0;
  params.min_effective_guides = 5.0;
  return params;
}

ChainReport run_directional(const char* label, Injected bug) {
  const SphereMixture target = sphere_target();
  const SphereGrid grid;
  DirectionalTestKernel kernel;
  kernel.guides = frozen_guides<Vec3>(target, 32, 4);
  kernel.params = directional_test_params();
  kernel.bug = bug;
  return run_chains<Vec3>(
      label, target, kernel, [&](const Vec3& w) { return grid.cell_of(w); },
      grid.probabilities(target), kChains, kSteps);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Formulas.

TEST(EnsembleSimilarity, MatchesEquation8AndScalesWithLengthScale) {
  const SimilarityParams paper;
  for (double distance : {0.001, 0.05, 0.5, 1.0, 2.0, 5.0}) {
    const double d = 1.0 / std::max(distance * distance, 1e-4);
    const double literal = 2.0 / (1.0 + std::exp(-d)) - 1.0;
    EXPECT_NEAR(vertex_similarity(Vec3(0.0f), Vec3(float(distance), 0.0f, 0.0f), paper), literal,
                1e-6 * literal);
  }
  EXPECT_NEAR(vertex_similarity(Vec3(0.0f), Vec3(1.0f, 0, 0), paper), 0.4621,
              1e-4);  // notes: ~0.46
  // A length scale l makes S(distance) = S_paper(distance / l).
  const SimilarityParams scaled{kPaperSimilarityEpsilon, 10.0};
  EXPECT_NEAR(vertex_similarity(Vec3(0.0f), Vec3(10.0f, 0, 0), scaled), 0.4621, 1e-4);
  // Eq. 9: the product over vertices.
  const std::vector<Vec3> path{Vec3(0.0f), Vec3(1.0f, 0, 0)},
      guide{Vec3(0.5f, 0, 0), Vec3(1.0f, 2.0f, 0)};
  const double product =
      vertex_similarity(path[0], guide[0], paper) * vertex_similarity(path[1], guide[1], paper);
  EXPECT_NEAR(std::exp(log_path_similarity(path, guide, paper)), product, 1e-12);
}

TEST(EnsembleSimilarity, GuideChoiceFollowsItsProbabilities) {
  const std::vector<double> log_weights{std::log(0.1), std::log(2.0), -800.0, std::log(0.7),
                                        std::log(1.2)};
  std::vector<double> probabilities(log_weights.size());
  normalise_log_weights(log_weights, probabilities);
  std::vector<double> observed(log_weights.size(), 0.0), expected(log_weights.size());
  Rng rng(kSeed, 7);
  const int draws = 200000;
  for (int i = 0; i < draws; ++i) {
    const GuideChoice choice = choose_guide(log_weights, rng);
    ASSERT_NEAR(choice.log_probability, guide_log_probability(log_weights, choice.index), 1e-12);
    observed[choice.index] += 1.0;
  }
  for (size_t n = 0; n < expected.size(); ++n) expected[n] = probabilities[n] * draws;
  EXPECT_GT(test::chi_square_test(observed, expected).p_value, 1e-3);
  // No usable weight: uniform, by the same rule in every function.
  const std::vector<double> none(4, -std::numeric_limits<double>::infinity());
  EXPECT_NEAR(guide_log_probability(none, 2), std::log(0.25), 1e-12);
}

TEST(EnsembleKernels, GreatArcMapIsTheSlerpWithParameterOneMinusLambda) {
  const Vec3 w1 = glm::normalize(Vec3(0.2f, 0.5f, 0.8f)),
             w2 = glm::normalize(Vec3(-0.6f, 0.1f, 0.4f));
  const double angle = std::acos(glm::dot(glm::dvec3(w1), glm::dvec3(w2)));
  for (double lambda : {0.5, 0.9, 1.0, 1.3, 2.0}) {
    const glm::dvec3 slerp = std::sin(lambda * angle) / std::sin(angle) * glm::dvec3(w1) +
                             std::sin((1.0 - lambda) * angle) / std::sin(angle) * glm::dvec3(w2);
    const auto arc = great_arc_point(w1, w2, lambda);
    ASSERT_TRUE(arc.has_value());
    EXPECT_LT(glm::length(glm::dvec3(*arc) - slerp), 1e-6);
    EXPECT_NEAR(std::acos(std::clamp(glm::dot(glm::dvec3(*arc), glm::dvec3(w2)), -1.0, 1.0)),
                lambda * angle, 1e-5);
  }
}

TEST(EnsembleKernels, VonMisesFisherSamplerMatchesItsDensity) {
  const Vec3 mean = glm::normalize(Vec3(0.3f, -0.4f, 0.5f));
  const SphereGrid grid;
  for (double kappa : {0.5, 8.0, 60.0}) {
    const SphereMixture single({{1.0, mean, kappa}});
    std::vector<double> observed(grid.cell_count(), 0.0), expected = grid.probabilities(single);
    Rng rng(kSeed, 11);
    const int draws = 100000;
    for (int i = 0; i < draws; ++i) observed[grid.cell_of(sample_vmf(mean, kappa, rng))] += 1.0;
    for (double& e : expected) e *= draws;
    EXPECT_GT(test::chi_square_test(observed, expected).p_value, 1e-3) << "kappa " << kappa;
  }
}

// Each kernel's reported ratio must equal what evaluating the move from its end points in
// both directions gives, and the move back must report the reciprocal ratio.
TEST(EnsembleKernels, RatiosAgreeWithEvaluationFromTheProposedState) {
  Rng rng(kSeed, 13);
  const PlaneMixture plane = plane_target();
  const SphereMixture sphere = sphere_target();
  const std::vector<Vec3> plane_guides = frozen_guides<Vec3>(PlaneTargetIn3d{}, 24, 3);
  const std::vector<Vec3> sphere_guides = frozen_guides<Vec3>(sphere, 32, 4);
  const AnisotropicParams anisotropic = anisotropic_test_params();
  DirectionalParams directional;
  directional.similarity.length_scale = 0.3;
  for (auto distribution :
       {StretchDistribution::InverseSqrt, StretchDistribution::UniformReciprocal}) {
    const StretchParams stretch{1.0, distribution};
    for (int i = 0; i < 200; ++i) {
      const Vec2 x = plane.sample(rng), v = plane.sample(rng);
      const LinearProposal p = propose_linear(x, v, stretch, rng);
      ASSERT_TRUE(p.valid);
      EXPECT_NEAR(linear_log_density_ratio_between(x, p.state, v, stretch), p.log_density_ratio,
                  1e-4);
      EXPECT_NEAR(linear_log_density_ratio_between(p.state, x, v, stretch), -p.log_density_ratio,
                  1e-4);
      const Vec3 w = sphere.sample(rng), g = sphere.sample(rng);
      const GreatArcProposal q = propose_great_arc(w, g, stretch, rng);
      if (!q.valid) continue;
      EXPECT_NEAR(great_arc_log_density_ratio_between(w, q.direction, g, stretch),
                  q.log_density_ratio, 1e-3);
      EXPECT_NEAR(great_arc_log_density_ratio_between(q.direction, w, g, stretch),
                  -q.log_density_ratio, 1e-3);
    }
  }
  for (int i = 0; i < 200; ++i) {
    const Vec3 x(plane.sample(rng), 0.0f);
    const AnisotropicProposal p =
        propose_anisotropic_on_plane(x, kPlaneNormal, {plane_guides, {}}, anisotropic, rng);
    EXPECT_NEAR(
        anisotropic_on_plane_log_density(x, kPlaneNormal, p.state, {plane_guides, {}}, anisotropic),
        p.log_forward_density, 1e-9);
    EXPECT_NEAR(
        anisotropic_on_plane_log_density(p.state, kPlaneNormal, x, {plane_guides, {}}, anisotropic),
        p.log_reverse_density, 1e-9);
    const Vec3 w = sphere.sample(rng);
    const DirectionalProposal q = propose_directional(w, {sphere_guides, {}}, directional, rng);
    EXPECT_NEAR(directional_log_density(w, q.direction, {sphere_guides, {}}, directional),
                q.log_forward_density, 1e-9);
    EXPECT_NEAR(directional_log_density(q.direction, w, {sphere_guides, {}}, directional),
                q.log_reverse_density, 1e-9);
  }
}

// The fallback branches are part of the kernels under test: with the test parameters both
// the fitted and the fallback branch must occur for states drawn from the targets, and the
// fitted width must vary with the state (else a dropped reverse density would be harmless).
TEST(EnsembleKernels, TestParametersExerciseFitAndFallback) {
  Rng rng(kSeed, 14);
  const PlaneTargetIn3d plane;
  const std::vector<Vec3> plane_guides = frozen_guides<Vec3>(plane, 24, 3);
  const SphereMixture sphere = sphere_target();
  const std::vector<Vec3> sphere_guides = frozen_guides<Vec3>(sphere, 32, 4);
  const DirectionalParams directional = directional_test_params();
  int plane_fallbacks = 0, sphere_fallbacks = 0;
  double smallest_kappa = 1e300, largest_kappa = 0.0;
  const int draws = 4000;
  for (int i = 0; i < draws; ++i) {
    plane_fallbacks += fit_tangent_gaussian(plane.sample(rng), kPlaneNormal, {plane_guides, {}},
                                            anisotropic_test_params())
                           .fallback;
    const VmfFit fit = fit_vmf(sphere.sample(rng), {sphere_guides, {}}, directional);
    sphere_fallbacks += fit.fallback;
    if (!fit.fallback) {
      smallest_kappa = std::min(smallest_kappa, fit.concentration);
      largest_kappa = std::max(largest_kappa, fit.concentration);
    }
  }
  std::printf(
      "fallback fractions: anisotropic %.3f, directional %.3f; fitted kappa in [%.2f, %.2f]\n",
      double(plane_fallbacks) / draws, double(sphere_fallbacks) / draws, smallest_kappa,
      largest_kappa);
  EXPECT_GT(plane_fallbacks, draws / 50);
  EXPECT_LT(plane_fallbacks, draws / 2);
  EXPECT_GT(sphere_fallbacks, draws / 100);
  EXPECT_LT(sphere_fallbacks, draws / 2);
  EXPECT_GT(largest_kappa, 3.0 * smallest_kappa);
}

// The general-surface hook: sample the point to cast through (z' from a fitted tangent
// Gaussian, or a direction of the vMF fallback), cast from an origin onto a tilted plane;
// the landing histogram must match the area density ray_cast_log_area_density reports. The
// p-value without the geometry Jacobian (the plane Gaussian's density at z, or the bare vMF
// density of the direction) is returned too: it must fail.
struct LandingTest {
  double p_with_jacobian = 0.0, p_without_jacobian = 1.0;
};

LandingTest landing_histogram(const TangentGaussian& kernel) {
  const Vec3 origin(0.3f, -0.2f, 2.0f);
  const glm::dvec3 surface_point(0.1, 0.0, -0.6),
      surface_normal = glm::normalize(glm::dvec3(0.5, 0.3, 1.0));
  const glm::dvec3 e1 = glm::normalize(glm::cross(surface_normal, glm::dvec3(0, 1, 0)));
  const glm::dvec3 e2 = glm::cross(surface_normal, e1);
  auto on_surface = [&](double a, double b) { return Vec3(surface_point + a * e1 + b * e2); };
  const PlaneGrid grid{2.0, 30};
  LandingTest result;
  for (bool with_jacobian : {true, false}) {
    auto density = [&](double a, double b) {
      const Vec3 x = on_surface(a, b);
      if (with_jacobian)
        return std::exp(ray_cast_log_area_density(kernel, origin, x, Vec3(surface_normal)));
      if (kernel.directional_fallback()) {
        const glm::dvec3 w = glm::normalize(glm::dvec3(x) - glm::dvec3(origin)),
                         mean = glm::normalize(kernel.centre - glm::dvec3(origin));
        return std::exp(vmf_log_pdf(kernel.fallback_concentration, glm::dot(w, mean)));
      }
      const auto z =
          project_through_onto_plane(origin, x, Vec3(kernel.centre), Vec3(kernel.normal));
      return std::exp(tangent_gaussian_log_pdf(kernel, *z));
    };
    std::vector<double> expected = grid.probabilities(density), observed(expected.size(), 0.0);
    Rng rng(kSeed, 12);
    const int draws = 200000;
    for (int i = 0; i < draws; ++i) {
      const glm::dvec3 z(sample_cast_target(kernel, origin, rng)), start(origin);
      const glm::dvec3 direction = z - start;
      const double t =
          glm::dot(surface_point - start, surface_normal) / glm::dot(direction, surface_normal);
      const glm::dvec3 hit = start + t * direction - surface_point;
      observed[t > 0.0 ? grid.cell_of(glm::dot(hit, e1), glm::dot(hit, e2))
                       : grid.cell_count() - 1] += 1.0;
    }
    for (double& e : expected) e *= draws;
    const double p = test::chi_square_test(observed, expected, 1e-3 * draws).p_value;
    std::printf("[ray-cast density, %s, jacobian %s] p = %.3g\n",
                kernel.directional_fallback() ? "vMF fallback" : "plane Gaussian",
                with_jacobian ? "on" : "off", p);
    (with_jacobian ? result.p_with_jacobian : result.p_without_jacobian) = p;
  }
  return result;
}

TEST(EnsembleKernels, RayCastAreaDensityMatchesLandingHistogram) {
  const std::vector<Vec3> guides{{0.6f, 0.1f, 0.0f},   {-0.5f, -0.2f, 0.1f}, {0.3f, 0.3f, -0.1f},
                                 {-0.2f, -0.1f, 0.0f}, {0.9f, 0.4f, 0.0f},   {-0.8f, -0.3f, 0.0f}};
  AnisotropicParams params;
  params.floor_sigma = 0.05;
  params.fallback_concentration = 20.0;  // set, but this fit does not fall back
  const TangentGaussian gaussian =
      fit_tangent_gaussian(Vec3(0.0f), kPlaneNormal, {guides, {}}, params);
  ASSERT_FALSE(gaussian.fallback);
  const LandingTest test = landing_histogram(gaussian);
  EXPECT_GT(test.p_with_jacobian, 1e-3);
  EXPECT_LT(test.p_without_jacobian, 1e-6);
}

// The paper's fallback: a vMF about the direction from the cast origin to the centre.
TEST(EnsembleKernels, RayCastVonMisesFisherFallbackMatchesLandingHistogram) {
  AnisotropicParams params;
  params.fallback_concentration = 20.0;  // about 0.2 rad wide: the lobe lands on the grid
  const TangentGaussian fallback = fit_tangent_gaussian(Vec3(0.0f), kPlaneNormal, {}, params);
  ASSERT_TRUE(fallback.directional_fallback());
  const LandingTest test = landing_histogram(fallback);
  EXPECT_GT(test.p_with_jacobian, 1e-3);
  EXPECT_LT(test.p_without_jacobian, 1e-6);
  // Without a concentration the fallback stays the isotropic Gaussian on the plane.
  params.fallback_concentration = 0.0;
  EXPECT_FALSE(fit_tangent_gaussian(Vec3(0.0f), kPlaneNormal, {}, params).directional_fallback());
}

// The scale mixture (--ensemble-aniso-multiscale): samples s z, z ~ N(0, Sigma), log s
// uniform on [log a, 0], land as the closed-form density says, and not as the single
// Gaussian's (the density a kernel that forgot the mixture would evaluate).
TEST(EnsembleKernels, ScaleMixtureSamplerMatchesItsDensity) {
  const std::vector<Vec3> guides{{0.6f, 0.1f, 0.0f},   {-0.5f, -0.2f, 0.1f}, {0.3f, 0.3f, -0.1f},
                                 {-0.2f, -0.1f, 0.0f}, {0.9f, 0.4f, 0.0f},   {-0.8f, -0.3f, 0.0f}};
  AnisotropicParams params;
  params.floor_sigma = 0.05;
  params.smallest_scale = 0.2;
  const TangentGaussian mixture =
      fit_tangent_gaussian(Vec3(0.0f), kPlaneNormal, {guides, {}}, params);
  ASSERT_FALSE(mixture.fallback);
  ASSERT_TRUE(mixture.scale_mixture());
  TangentGaussian single = mixture;
  single.smallest_scale = 1.0;
  const PlaneGrid grid{1.5, 24};
  auto density_of = [&](const TangentGaussian& kernel) {
    return [&kernel](double x, double y) {
      return std::exp(tangent_gaussian_log_pdf(kernel, Vec3(float(x), float(y), 0.0f)));
    };
  };
  std::vector<double> observed(grid.cell_count(), 0.0);
  Rng rng(kSeed, 13);
  const int draws = 200000;
  for (int i = 0; i < draws; ++i) {
    const Vec3 z = sample_tangent_gaussian(mixture, rng);
    observed[grid.cell_of(z.x, z.y)] += 1.0;
  }
  std::vector<double> expected = grid.probabilities(density_of(mixture)),
                      as_single = grid.probabilities(density_of(single));
  for (double& e : expected) e *= draws;
  for (double& e : as_single) e *= draws;
  const double p = test::chi_square_test(observed, expected, 1e-3 * draws).p_value;
  const double p_single = test::chi_square_test(observed, as_single, 1e-3 * draws).p_value;
  std::printf("[scale mixture, a = 0.2] p = %.3g; against the single Gaussian p = %.3g\n", p,
              p_single);
  EXPECT_GT(p, 1e-3);
  EXPECT_LT(p_single, 1e-6);
  // The density's limit at the centre is finite and above the single Gaussian's peak.
  const double at_centre = std::exp(tangent_gaussian_log_pdf(mixture, Vec3(0.0f)));
  EXPECT_TRUE(std::isfinite(at_centre));
  EXPECT_GT(at_centre, std::exp(tangent_gaussian_log_pdf(single, Vec3(0.0f))));
}

// A cast from an origin on (or within rounding of) the Gaussian's plane runs along the plane:
// the plane point is then no function of the hit, and the density must be zero rather than
// a number made of rounding errors; a slightly raised origin gives an ordinary density.
TEST(EnsembleKernels, RayCastAlongThePlaneHasZeroDensity) {
  AnisotropicParams params;
  const TangentGaussian gaussian = fit_tangent_gaussian(Vec3(0.0f), kPlaneNormal, {}, params);
  const Vec3 surface_point(0.0f, 1.0f, 2e-6f), surface_normal(0.0f, -1.0f, 0.0f);  // a wall
  for (const float height : {0.0f, 1e-6f, -1e-6f}) {
    const Vec3 origin(0.3f, -2.0f, height);
    EXPECT_EQ(ray_cast_log_area_density(gaussian, origin, surface_point, surface_normal),
              -std::numeric_limits<double>::infinity())
        << height;
  }
  const Vec3 raised(0.3f, -2.0f, 1.0f);
  EXPECT_TRUE(std::isfinite(
      ray_cast_log_area_density(gaussian, raised, Vec3(0.01f, 0.02f, 0.0f), kPlaneNormal)));
  // Without the guard (the injected bug's setting) the grazing ray gets a finite density.
  EXPECT_TRUE(std::isfinite(ray_cast_log_area_density(gaussian, Vec3(0.3f, -2.0f, -1e-6f),
                                                      surface_point, surface_normal, 0.0)));
}

// ---------------------------------------------------------------------------------------
// Each kernel alone keeps pi invariant; each injected bug does not.

TEST(EnsembleKernelChains, LinearGoodmanWeareKeepsTarget) {
  expect_matches_target(
      run_linear("linear GW", StretchDistribution::InverseSqrt, 1.0, Injected::None));
}
TEST(EnsembleKernelChains, LinearUniformReciprocalKeepsTarget) {
  expect_matches_target(
      run_linear("linear uniform", StretchDistribution::UniformReciprocal, 1.0, Injected::None));
}
TEST(EnsembleKernelChains, LinearUniformSymmetricKeepsTarget) {
  expect_matches_target(run_linear("linear uniform 1+-b", StretchDistribution::UniformSymmetric,
                                   0.6, Injected::None));
}
TEST(EnsembleKernelChains, LinearDroppedReverseDensityIsDetected) {
  expect_detected(run_linear("linear GW, bug: no ratio", StretchDistribution::InverseSqrt, 1.0,
                             Injected::DroppedReverseDensity));
}
TEST(EnsembleKernelChains, LinearUniformWithLambdaJacobianIsDetected) {
  expect_detected(run_linear("linear uniform, bug: ratio lambda",
                             StretchDistribution::UniformReciprocal, 1.0, Injected::WrongJacobian));
}
TEST(EnsembleKernelChains, LinearIgnoredSelectionProbabilityIsDetected) {
  expect_detected(run_linear("linear GW, bug: no P(n|y)/P(n|x)", StretchDistribution::InverseSqrt,
                             1.0, Injected::IgnoredSelection));
}

TEST(EnsembleKernelChains, GreatArcKeepsTarget) {
  expect_matches_target(run_great_arc("great arc", Injected::None));
}
TEST(EnsembleKernelChains, GreatArcWithPrintedEquation10IsDetected) {
  expect_detected(run_great_arc("great arc, bug: eq. 10 as printed", Injected::WrongJacobian));
}
TEST(EnsembleKernelChains, GreatArcDroppedReverseDensityIsDetected) {
  expect_detected(run_great_arc("great arc, bug: no ratio", Injected::DroppedReverseDensity));
}
TEST(EnsembleKernelChains, GreatArcIgnoredSelectionProbabilityIsDetected) {
  expect_detected(run_great_arc("great arc, bug: no P(n|y)/P(n|x)", Injected::IgnoredSelection));
}

TEST(EnsembleKernelChains, AnisotropicKeepsTarget) {
  expect_matches_target(run_anisotropic("anisotropic", Injected::None));
}
TEST(EnsembleKernelChains, AnisotropicAsPrintedKeepsTarget) {
  expect_matches_target(run_anisotropic("anisotropic, eq. 11 as printed", Injected::None, true));
  expect_detected(run_anisotropic("anisotropic, eq. 11 as printed, bug: Sigma not refitted",
                                  Injected::SigmaNotRefitted, true));
}
TEST(EnsembleKernelChains, AnisotropicScaleMixtureKeepsTarget) {
  expect_matches_target(
      run_anisotropic("anisotropic, scale mixture from 0.05", Injected::None, true, 0.05));
  expect_detected(run_anisotropic("anisotropic, scale mixture, bug: single Gaussian's densities",
                                  Injected::MixtureAsGaussian, true, 0.05));
}
TEST(EnsembleKernelChains, AnisotropicDroppedReverseDensityIsDetected) {
  expect_detected(run_anisotropic("anisotropic, bug: no ratio", Injected::DroppedReverseDensity));
}
TEST(EnsembleKernelChains, AnisotropicSigmaNotRefittedIsDetected) {
  // On the plane, the forward Sigma reused for the reverse density is the same as dropping
  // the reverse density (a recentred Gaussian is symmetric in its two points).
  expect_detected(
      run_anisotropic("anisotropic, bug: Sigma not refitted", Injected::SigmaNotRefitted));
}
TEST(EnsembleKernelChains, AnisotropicFallbackNotRedecidedIsDetected) {
  expect_detected(
      run_anisotropic("anisotropic, bug: fallback copied", Injected::FallbackNotRedecided));
}

TEST(EnsembleKernelChains, DirectionalKeepsTarget) {
  expect_matches_target(run_directional("directional", Injected::None));
}
TEST(EnsembleKernelChains, DirectionalDroppedReverseDensityIsDetected) {
  expect_detected(run_directional("directional, bug: no ratio", Injected::DroppedReverseDensity));
}
