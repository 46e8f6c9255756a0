// The one-sample light/BSDF mixture and Lu's second-order split (sampling/
// mixture_direct_estimator.h, integrators/mis_alpha_map.h) against analytic answers: a
// diffuse floor under a square light (Lambert's polygon formula) and a normalised Phong
// plane under a constant sky (the furnace: k_d + k_s of the sky, seen along the normal).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "emlt/integrators/direct_integrator.h"
#include "emlt/sampling/direct_lighting.h"
#include "emlt/sampling/direct_sample.h"
#include "emlt/sampling/mixture_direct_estimator.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "support/bsdf_harness.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::add_material;
using test::add_quad;
using test::camera_at;

constexpr float kFloorAlbedo = 0.7f, kLightRadiance = 10.0f;

// A diffuse floor (y = 0, facing up) under a 1 x 1 square light at height 2 facing down.
std::unique_ptr<Scene> floor_and_light() {
  SceneDescription d;
  d.source = "floor-and-light";
  const int floor = add_material(d, make_lambertian(Rgb(kFloorAlbedo)));
  const int black = add_material(d, make_lambertian(Rgb(0.0f)));
  add_quad(d, Vec3(-4, 0, -4), Vec3(-4, 0, 4), Vec3(4, 0, 4), Vec3(4, 0, -4), floor);
  add_quad(d, Vec3(-0.5f, 2, -0.5f), Vec3(0.5f, 2, -0.5f), Vec3(0.5f, 2, 0.5f),
           Vec3(-0.5f, 2, 0.5f), black, Rgb(kLightRadiance));
  d.camera = camera_at(Vec3(0, 3, -5), Vec3(0, 0, 0), 24);
  return Scene::build(std::move(d));
}

// Radiance the floor reflects at p: albedo / pi times the irradiance of the light, by
// Lambert's formula E = L/2 sum_i theta_i n . (v_i x v_i+1)/|v_i x v_i+1|.
double floor_radiance(const Vec3& p) {
  const DVec3 corners[4] = {{-0.5, 2, -0.5}, {0.5, 2, -0.5}, {0.5, 2, 0.5}, {-0.5, 2, 0.5}};
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    const DVec3 a = glm::normalize(corners[i] - DVec3(p)),
                b = glm::normalize(corners[(i + 1) % 4] - DVec3(p));
    const DVec3 c = glm::cross(a, b);
    sum += std::acos(glm::clamp(glm::dot(a, b), -1.0, 1.0)) * c.y / glm::length(c);
  }
  const double irradiance = 0.5 * kLightRadiance * std::abs(sum);
  return kFloorAlbedo / kPi * irradiance;
}

// A large plane (y = 0) of `bsdf` under a constant sky of radiance 1.
std::unique_ptr<Scene> plane_under_sky(BsdfPtr bsdf) {
  SceneDescription d;
  d.source = "plane-under-sky";
  const int m = add_material(d, std::move(bsdf));
  add_quad(d, Vec3(-100, 0, -100), Vec3(-100, 0, 100), Vec3(100, 0, 100), Vec3(100, 0, -100), m);
  d.environment.kind = EnvironmentDesc::Kind::Constant;
  d.environment.radiance = Rgb(1.0f);
  d.camera = camera_at(Vec3(0, 2, 0), Vec3(0.1f, 0, 0.1f), 16, Vec3(0, 0, 1));
  return Scene::build(std::move(d));
}

SurfaceHit hit_below(const Scene& scene, const Vec3& from) {
  SurfaceHit hit;
  EXPECT_TRUE(scene.intersect(Ray{from, Vec3(0, -1, 0)}, hit));
  return hit;
}

struct Moments {
  double mean = 0.0, variance = 0.0, standard_error = 0.0;
};

// `trials` independent estimates (green channel) of `estimate(rng)`.
template <class Estimate>
Moments moments_of(int trials, uint64_t seed, Estimate&& estimate) {
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < trials; ++i) {
    Rng rng(seed, uint64_t(i));
    const double v = estimate(rng).y;
    sum += v;
    sum2 += v * v;
  }
  Moments m;
  m.mean = sum / trials;
  m.variance = std::max(sum2 / trials - m.mean * m.mean, 0.0);
  m.standard_error = std::sqrt(m.variance / trials);
  return m;
}

// Normalised Phong: k_d / pi + k_s (n + 2) / (2 pi) cos^n; seen along the normal under a
// sky of 1 the lobe is whole, so the plane reflects k_d + k_s.
constexpr float kPhongDiffuse = 0.3f, kPhongSpecular = 0.6f, kPhongExponent = 40.0f;

}  // namespace

TEST(MixtureDirect, DirectionsFollowTheMixtureDensity) {
  // Directions drawn by light sampling with probability alpha and by the BSDF otherwise,
  // histogrammed over (cos theta, phi) of the shading frame, against alpha p_L + (1 - alpha)
  // p_B: the constant sky's p_L = 1/(4 pi) over the sphere, p_B the Phong BSDF's density.
  const auto sky =
      plane_under_sky(make_phong(kPhongExponent, Rgb(kPhongSpecular), Rgb(kPhongDiffuse)));
  const SurfaceHit hit = hit_below(*sky, Vec3(0, 1, 0));
  const Vec3 wo(0, 1, 0), wo_local = hit.shading.to_local(wo);
  const BsdfContext ctx{hit.uv, TransportMode::Radiance, hit.vertex_color};
  const int cos_bins = 16, phi_bins = 16, samples = 200000;
  for (double alpha : {0.3, 0.7}) {
    std::vector<double> observed(cos_bins * phi_bins + 1, 0.0), expected(observed.size(), 0.0);
    Rng rng(61, uint64_t(alpha * 10));
    int drawn = 0;
    for (int n = 0; n < samples; ++n) {
      const bool light = rng.uniform() < alpha;
      const float u = rng.uniform();
      const DirectSample s = light ? draw_light_direction(*sky, hit, wo, u, rng.uniform2())
                                   : draw_bsdf_direction(*sky, hit, wo, u, rng.uniform2());
      if (!(s.own_pdf > 0.0f) || s.delta) continue;
      const Vec3 w = hit.shading.to_local(s.wi);
      double phi = std::atan2(double(w.y), double(w.x));
      if (phi < 0.0) phi += 2.0 * kPi;
      const int i =
          std::min(cos_bins - 1, int((glm::clamp(double(w.z), -1.0, 1.0) + 1.0) * 0.5 * cos_bins));
      const int j = std::min(phi_bins - 1, int(phi / (2.0 * kPi) * phi_bins));
      observed[size_t(i * phi_bins + j)] += 1.0;
      ++drawn;
    }
    observed.back() = samples - drawn;
    const test::DirectionalDensity density = [&](const Vec3& w) {
      return alpha / (4.0 * kPi) + (1.0 - alpha) * double(hit.bsdf->pdf(ctx, wo_local, w));
    };
    double total = 0.0;
    for (int i = 0; i < cos_bins; ++i) {
      const double theta0 = std::acos(-1.0 + 2.0 * (i + 1) / cos_bins);
      const double theta1 = std::acos(-1.0 + 2.0 * i / cos_bins);
      for (int j = 0; j < phi_bins; ++j) {
        const double phi0 = 2.0 * kPi * j / phi_bins, phi1 = 2.0 * kPi * (j + 1) / phi_bins;
        const auto f = [&](double theta, double phi) {
          return density(test::spherical_direction(std::cos(theta), phi)) * std::sin(theta);
        };
        const double coarse = test::integrate_2d(f, theta0, theta1, phi0, phi1, 4);
        const double mass =
            test::detail::integrate_patch(density, theta0, theta1, phi0, phi1, coarse, 6);
        expected[size_t(i * phi_bins + j)] = mass * samples;
        total += mass;
      }
    }
    expected.back() = std::max(0.0, 1.0 - total) * samples;
    const test::ChiSquareResult chi2 = test::chi_square_test(observed, expected);
    EXPECT_GT(chi2.p_value, 1e-3) << "alpha " << alpha << ": chi2 " << chi2.statistic << " dof "
                                  << chi2.degrees_of_freedom << ", density mass " << total;
  }
}

TEST(MixtureDirect, UnbiasedForAnyFixedAlpha) {
  const auto lit = floor_and_light();
  const auto sky =
      plane_under_sky(make_phong(kPhongExponent, Rgb(kPhongSpecular), Rgb(kPhongDiffuse)));
  const Vec3 p(0.3f, 0.0f, -0.2f);
  const SurfaceHit floor_hit = hit_below(*lit, p + Vec3(0, 1, 0));
  const SurfaceHit phong_hit = hit_below(*sky, Vec3(0, 1, 0));
  const double floor_expected = floor_radiance(p), phong_expected = kPhongDiffuse + kPhongSpecular;
  for (double alpha : {0.0, 0.1, 0.5, 0.9, 1.0}) {
    const Moments a = moments_of(20000, 7, [&](Rng& rng) {
      return estimate_direct_mixture(*lit, floor_hit, Vec3(0, 1, 0), rng, alpha, 8);
    });
    EXPECT_NEAR(a.mean, floor_expected, 4.0 * a.standard_error + 1e-4 * floor_expected)
        << "floor, alpha " << alpha;
    const Moments b = moments_of(20000, 8, [&](Rng& rng) {
      return estimate_direct_mixture(*sky, phong_hit, Vec3(0, 1, 0), rng, alpha, 8);
    });
    EXPECT_NEAR(b.mean, phong_expected, 4.0 * b.standard_error + 1e-4) << "phong, alpha " << alpha;
  }
}

TEST(MixtureDirect, SecondOrderOnlineIsUnbiased) {
  const auto lit = floor_and_light();
  const auto sky =
      plane_under_sky(make_phong(kPhongExponent, Rgb(kPhongSpecular), Rgb(kPhongDiffuse)));
  const Vec3 p(-0.8f, 0.0f, 0.4f);
  const SurfaceHit floor_hit = hit_below(*lit, p + Vec3(0, 1, 0));
  const SurfaceHit phong_hit = hit_below(*sky, Vec3(0, 1, 0));
  for (double pilot : {0.25, 0.5}) {
    const SecondOrderSplit split{pilot, 0.025};
    const Moments a = moments_of(20000, 9, [&](Rng& rng) {
      return estimate_direct_second_order(*lit, floor_hit, Vec3(0, 1, 0), rng, 16, split);
    });
    EXPECT_NEAR(a.mean, floor_radiance(p), 4.0 * a.standard_error) << pilot;
    const Moments b = moments_of(20000, 10, [&](Rng& rng) {
      return estimate_direct_second_order(*sky, phong_hit, Vec3(0, 1, 0), rng, 16, split);
    });
    EXPECT_NEAR(b.mean, kPhongDiffuse + kPhongSpecular, 4.0 * b.standard_error) << pilot;
  }
}

TEST(MixtureDirect, HalfAndHalfPilotIsTheBalanceHeuristic) {
  // Eq. 5.3: balance-heuristic MIS with n samples of each strategy is the mixture at alpha
  // 1/2 with 2n directions. The pilot draws the same numbers in the same order as the
  // multi-sample estimator, so the two agree sample for sample, not only on average.
  const auto lit = floor_and_light();
  const auto sky =
      plane_under_sky(make_phong(kPhongExponent, Rgb(kPhongSpecular), Rgb(kPhongDiffuse)));
  for (const Scene* scene : {lit.get(), sky.get()}) {
    const SurfaceHit hit = hit_below(*scene, Vec3(0.2f, 1, 0.1f));
    DirectLightingOptions balance;
    balance.samples = 4;
    balance.heuristic = MisHeuristic::Balance;
    for (int i = 0; i < 2000; ++i) {
      Rng a(21, uint64_t(i)), b(21, uint64_t(i));
      const Rgb multi = estimate_direct_lighting(*scene, hit, Vec3(0, 1, 0), a, balance);
      const Rgb mixture = estimate_direct_pilot(*scene, hit, Vec3(0, 1, 0), b, 8, nullptr);
      ASSERT_NEAR(mixture.y, multi.y, 1e-5f * std::max(1.0f, multi.y))
          << scene->description().source << " " << i;
    }
  }
}

TEST(MixtureDirect, OnlineAlphaConvergesToEquation54) {
  // A Lambertian plane under a constant sky: f = (rho/pi) cos, p_B = cos/pi, p_L = 1/(4 pi).
  // Eq. 5.4 integrated over mu = cos(theta): alpha = 1/2 + (1/4) A/B with
  // A = int mu^2 (1 - 4mu)/(1 + 4mu)^2, B = int mu^2 (1 - 4mu)^2/(1 + 4mu)^3 on [0, 1].
  double first = 0.0, second = 0.0;
  const int cells = 200000;
  for (int i = 0; i < cells; ++i) {
    const double mu = (i + 0.5) / cells;
    first += mu * mu * (1 - 4 * mu) / std::pow(1 + 4 * mu, 2.0);
    second += mu * mu * std::pow(1 - 4 * mu, 2.0) / std::pow(1 + 4 * mu, 3.0);
  }
  const double expected = 0.5 + 0.25 * first / second;  // 0.0077: BSDF sampling is exact here
  const auto scene = plane_under_sky(make_lambertian(Rgb(0.5f)));
  const SurfaceHit hit = hit_below(*scene, Vec3(0, 1, 0));
  SecondOrderAlpha moments;
  for (int i = 0; i < 2000; ++i) {
    Rng rng(31, uint64_t(i));
    estimate_direct_pilot(*scene, hit, Vec3(0, 1, 0), rng, 128, &moments);
  }
  EXPECT_NEAR(moments.unclamped(), expected, 0.003);
  // And the clamp holds the online split at 0.025.
  double used = 0.0;
  Rng rng(32, 0);
  estimate_direct_second_order(*scene, hit, Vec3(0, 1, 0), rng, 4096, SecondOrderSplit{0.5, 0.025},
                               &used);
  EXPECT_NEAR(used, 0.025, 1e-9);
}

TEST(MixtureDirect, SpecularSurfaceSpendsEveryDirectionOnTheBsdf) {
  // A mirror under a constant sky of 1 reflects exactly its reflectance; light sampling can
  // never find the mirror direction, so the online split gives the BSDF everything.
  const auto scene = plane_under_sky(make_mirror(Rgb(0.8f)));
  const SurfaceHit hit = hit_below(*scene, Vec3(0, 1, 0));
  double used = -1.0;
  Rng rng(51, 0);
  const Rgb value = estimate_direct_second_order(*scene, hit, Vec3(0, 1, 0), rng, 16,
                                                 SecondOrderSplit{0.5, 0.025}, &used);
  EXPECT_EQ(used, 0.0);
  EXPECT_NEAR(value.y, 0.8f, 1e-5f);
}

TEST(MixtureDirect, SecondOrderBeatsBalanceWhereOneStrategyIsBetter) {
  // Under the constant sky BSDF sampling of a Lambertian plane is exact: the split moves
  // towards it. Under the small light light sampling is far better: it moves the other way.
  const auto sky = plane_under_sky(make_lambertian(Rgb(0.5f)));
  const auto lit = floor_and_light();
  for (const Scene* scene : {sky.get(), lit.get()}) {
    const SurfaceHit hit = hit_below(*scene, Vec3(0.1f, 1, 0.2f));
    DirectLightingOptions balance;
    balance.samples = 16;
    balance.heuristic = MisHeuristic::Balance;
    const Moments b = moments_of(8000, 41, [&](Rng& rng) {
      return estimate_direct_lighting(*scene, hit, Vec3(0, 1, 0), rng, balance);
    });
    const Moments online = moments_of(8000, 42, [&](Rng& rng) {
      return estimate_direct_second_order(*scene, hit, Vec3(0, 1, 0), rng, 32,
                                          SecondOrderSplit{0.5, 0.025});
    });
    EXPECT_LT(online.variance, 0.75 * b.variance) << scene->description().source;
    EXPECT_NEAR(online.mean, b.mean, 4.0 * (online.standard_error + b.standard_error));
  }
}

TEST(MixtureDirect, PreprocessedRenderIsUnbiasedAndTheSameAtAnyThreadCount) {
  const auto scene = floor_and_light();
  RenderSettings s;
  s.progress = false;
  s.spp = 4;
  s.direct_samples = 8;
  ProgressReporter quiet(false);
  s.mis = MisHeuristic::Balance;
  s.spp = 64;
  const Image reference = DirectIntegrator().render(*scene, s, quiet).image;
  s.spp = 16;
  s.mis = MisHeuristic::SecondOrder;
  s.mis_alpha_estimate = MisAlphaEstimate::Preprocessed;
  s.mis_alpha_samples = 64;
  s.threads = 1;
  const Image one = DirectIntegrator().render(*scene, s, quiet).image;
  s.threads = 2;
  const Image two = DirectIntegrator().render(*scene, s, quiet).image;
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Rgb)), 0);
  double a = 0.0, b = 0.0;
  for (size_t i = 0; i < one.pixels.size(); ++i) {
    a += one.pixels[i].y;
    b += reference.pixels[i].y;
  }
  EXPECT_NEAR(a / b, 1.0, 0.01);
}
