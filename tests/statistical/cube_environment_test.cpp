// The cube-map environment (scene/cube_environment.h) and Lu's per-receiver cube-face
// sampler (sampling/cube_balanced_sampler.h): exact texel solid angles, the pdf against
// its own histogram and its normalisation, Eq. 3.4's face weights against a computation of
// their own, and renders of environment-lit floors against analytic and lat-long answers.
#include "emlt/scene/cube_environment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/core/warp.h"
#include "emlt/integrators/direct_integrator.h"
#include "emlt/integrators/path_tracer.h"
#include "emlt/run/progress.h"
#include "emlt/sampling/cube_balanced_sampler.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// The synthetic sun and sky of the design notes (section 6.4): sky of radiance 1 and a sun
// lobe 1000 max(0, w.s)^100, 45 degrees above the horizon; lat-long, rasterised at texel
// centres.
const Vec3 kSun = glm::normalize(Vec3(0.6f, 1.0f, -0.8f));  // (0.6, 0, -0.8) is unit: 45 degrees

Image sun_sky_map(int width) {
  Image map(width, width / 2);
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const Vec3 w = latlong_to_direction(Vec2((x + 0.5f) / map.width, (y + 0.5f) / map.height));
      const float lobe = std::pow(std::max(0.0f, glm::dot(w, kSun)), 100.0f);
      map.at(x, y) = Rgb(1.0f) + 1000.0f * lobe * Rgb(1.0f, 0.9f, 0.7f);
    }
  }
  return map;
}

// Receivers of section 6.4's table, and one in no special position.
std::vector<CubeReceiver> receivers() {
  const Vec3 horizontal_sun = glm::normalize(Vec3(kSun.x, 0.0f, kSun.z));
  const Vec3 side = glm::normalize(glm::cross(horizontal_sun, Vec3(0, 1, 0)));
  return {CubeReceiver{Vec3(0, 1, 0), false},    // up: 45 degrees to the sun
          CubeReceiver{-horizontal_sun, false},  // horizontal, facing away (135 degrees)
          CubeReceiver{side, false},             // 90 degrees to the sun
          CubeReceiver{glm::normalize(Vec3(-0.3f, 0.5f, 0.8f)), false},
          CubeReceiver{glm::normalize(Vec3(0.2f, -0.9f, 0.4f)), true}};  // transmitting
}

// The face-coordinate Jacobian dw / (du dv) at a face point.
double jacobian(const Vec2& uv) {
  return std::pow(1.0 + double(uv.x) * uv.x + double(uv.y) * uv.y, -1.5);
}

}  // namespace

// Section 2.5's closed form: the texels of the six faces tile the sphere, so their solid
// angles sum to 4 pi (to round-off), each agrees with a fine quadrature of its integral, and
// the midpoint rule is off by the amounts the design notes computed (5.98e-5 of the total,
// 2.44e-4 for the worst texel, at 64 per face).
TEST(CubeEnvironment, TexelSolidAnglesAreExact) {
  for (const int n : {1, 7, 64, 256}) {
    double total = 0.0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) total += CubeEnvironment::texel_solid_angle(n, i, j);
    EXPECT_NEAR(6.0 * total, 4.0 * kPiD, 1e-12 * 4.0 * kPiD) << n << " per face";
  }
  // Independent check of single texels: Simpson's rule on the integrand itself.
  for (const auto& [n, i, j] : {std::tuple{64, 0, 0}, {64, 17, 40}, {64, 31, 32}, {7, 3, 6}}) {
    const double a = -1.0 + 2.0 * i / n, c = -1.0 + 2.0 * j / n, h = 2.0 / n;
    const double quadrature =
        test::integrate_2d([](double u, double v) { return std::pow(1.0 + u * u + v * v, -1.5); },
                           a, a + h, c, c + h, 256);
    EXPECT_NEAR(CubeEnvironment::texel_solid_angle(n, i, j), quadrature, 1e-12 * quadrature)
        << "texel (" << i << ", " << j << ") of " << n;
  }
  double exact = 0.0, midpoint = 0.0, worst = 0.0;
  for (int j = 0; j < 64; ++j) {
    for (int i = 0; i < 64; ++i) {
      const double e = CubeEnvironment::texel_solid_angle(64, i, j);
      const double m = CubeEnvironment::texel_solid_angle_midpoint(64, i, j);
      exact += e;
      midpoint += m;
      worst = std::max(worst, std::abs(m - e) / e);
    }
  }
  EXPECT_NEAR(std::abs(midpoint - exact) / exact, 5.98e-5, 0.01e-5);
  EXPECT_NEAR(worst, 2.44e-4, 0.01e-4);
}

TEST(CubeEnvironment, FacesAndDirectionsRoundTrip) {
  Rng rng(3, 0);
  for (int k = 0; k < 10000; ++k) {
    const Vec3 w = square_to_uniform_sphere(rng.uniform2());
    Vec2 uv;
    const int face = CubeEnvironment::face_of(w, &uv);
    ASSERT_LE(std::abs(uv.x), 1.0f);
    ASSERT_LE(std::abs(uv.y), 1.0f);
    const Vec3 back = CubeEnvironment::direction(face, uv);
    ASSERT_NEAR(glm::dot(back, w), 1.0f, 1e-6f);
  }
}

// The sampler's density integrates to one over the sphere for every receiver. Within a
// texel the density is a constant times (1 + u^2 + v^2)^(3/2), so the midpoint sum of
// pdf x Jacobian x area over a grid finer than the texels is exact up to round-off.
TEST(CubeBalancedSampler, PdfIntegratesToOne) {
  const EnvironmentMap env(sun_sky_map(128), 1.0f, Mat3(1.0f));
  const CubeEnvironment cube(env, 16);
  for (const CubeReceiver& r : receivers()) {
    for (const auto fault : {CubeSamplerFault::None, CubeSamplerFault::PdfWithoutFaceChoice}) {
      const int sub = 3 * cube.resolution();
      const double area = (2.0 / sub) * (2.0 / sub);
      double total = 0.0;
      for (int f = 0; f < CubeEnvironment::kFaces; ++f) {
        for (int j = 0; j < sub; ++j) {
          for (int i = 0; i < sub; ++i) {
            const Vec2 uv(float(-1.0 + (i + 0.5) * 2.0 / sub), float(-1.0 + (j + 0.5) * 2.0 / sub));
            total += double(cube_balanced_pdf(cube, r, CubeEnvironment::direction(f, uv), fault)) *
                     jacobian(uv) * area;
          }
        }
      }
      if (fault == CubeSamplerFault::None)
        EXPECT_NEAR(total, 1.0, 1e-5) << "normal " << r.normal.x << " " << r.normal.y;
      else
        EXPECT_GT(std::abs(total - 1.0), 0.1) << "the test cannot tell a missing face choice";
    }
  }
}

// Chi-square of sampled directions over cells of 2 x 2 texels on every face, against the
// evaluated density integrated over each cell (exactly, as above): the sampler draws what
// its pdf says, for several receivers. With the face's probability left out of the density
// the same samples fail.
TEST(CubeBalancedSampler, HistogramMatchesPdf) {
  const EnvironmentMap env(sun_sky_map(128), 1.0f, Mat3(1.0f));
  const CubeEnvironment cube(env, 16);
  const int cells = 8, per_cell = cube.resolution() / cells, sub = 4 * per_cell;
  const auto cell_of = [&](const Vec3& w) {
    Vec2 uv;
    const int face = CubeEnvironment::face_of(w, &uv);
    const int i = std::clamp(int((uv.x + 1.0f) * 0.5f * cells), 0, cells - 1);
    const int j = std::clamp(int((uv.y + 1.0f) * 0.5f * cells), 0, cells - 1);
    return size_t((face * cells + j) * cells + i);
  };
  const auto expected_counts = [&](const CubeReceiver& r, CubeSamplerFault fault, double samples) {
    std::vector<double> expected(size_t(6 * cells * cells), 0.0);
    const int n = cells * sub;  // quadrature points per face edge
    const double area = (2.0 / n) * (2.0 / n);
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Vec2 uv(float(-1.0 + (i + 0.5) * 2.0 / n), float(-1.0 + (j + 0.5) * 2.0 / n));
          const size_t cell = size_t((f * cells + j / sub) * cells + i / sub);
          expected[cell] +=
              samples *
              double(cube_balanced_pdf(cube, r, CubeEnvironment::direction(f, uv), fault)) *
              jacobian(uv) * area;
        }
    return expected;
  };
  const int samples = 100000;
  uint64_t seed = 40;
  for (const CubeReceiver& r : receivers()) {
    Rng rng(seed++, 0);
    std::vector<double> observed(size_t(6 * cells * cells), 0.0);
    for (int k = 0; k < samples; ++k) {
      float pdf = 0.0f;
      const auto w = sample_cube_balanced(cube, r, rng.uniform2(), &pdf);
      ASSERT_TRUE(w.has_value());
      ASSERT_NEAR(pdf, cube_balanced_pdf(cube, r, *w), 1e-5f * pdf);
      observed[cell_of(*w)] += 1.0;
    }
    const auto good =
        test::chi_square_test(observed, expected_counts(r, CubeSamplerFault::None, samples));
    EXPECT_GT(good.p_value, 1e-3) << "chi2 " << good.statistic << " dof " << good.degrees_of_freedom
                                  << ", normal " << r.normal.x << " " << r.normal.y << " "
                                  << r.normal.z;
    const auto bad = test::chi_square_test(
        observed, expected_counts(r, CubeSamplerFault::PdfWithoutFaceChoice, samples));
    EXPECT_LT(bad.p_value, 1e-9) << "the test cannot tell a missing face probability";
  }
}

// Eq. 3.4 from scratch: corners (+-1, +-1, +-1)/sqrt 3 of the face with the major axis, the
// face's luminance integral by a fine quadrature of the map's own radiance. The weights agree
// to the table's own quadrature error (a few per mille); a face entirely below a one-sided
// receiver's horizon gets none. Without I_f (F_f alone) the weights are far off.
TEST(CubeBalancedSampler, FaceWeightsFollowEquation34) {
  const EnvironmentMap env(sun_sky_map(256), 1.0f, Mat3(1.0f));
  const CubeEnvironment cube(env, 64);
  double mass[6];
  for (int f = 0; f < 6; ++f) {
    const int n = 256;
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec2 uv(float(-1.0 + (i + 0.5) * 2.0 / n), float(-1.0 + (j + 0.5) * 2.0 / n));
        sum += double(luminance(env.radiance(CubeEnvironment::direction(f, uv)))) *
               CubeEnvironment::texel_solid_angle(n, i, j);
      }
    mass[f] = sum;
  }
  for (const CubeReceiver& r : receivers()) {
    double expected[6], total = 0.0;
    for (int f = 0; f < 6; ++f) {
      const int axis = f / 2;
      const float sign = f % 2 ? -1.0f : 1.0f;
      double form = 0.0;
      for (const float a : {-1.0f, 1.0f})
        for (const float b : {-1.0f, 1.0f}) {
          Vec3 c(0.0f);
          c[axis] = sign;
          c[(axis + 1) % 3] = a;
          c[(axis + 2) % 3] = b;
          const double cosine = double(glm::dot(r.normal, c)) / std::sqrt(3.0);
          form += r.two_sided ? std::abs(cosine) : std::max(cosine, 0.0);
        }
      expected[f] = form * mass[f];
      total += expected[f];
    }
    const auto mu = cube_face_weights(cube, r);
    const auto wrong = cube_face_weights(cube, r, CubeSamplerFault::FaceWeightWithoutMass);
    double worst_wrong = 0.0;
    for (int f = 0; f < 6; ++f) {
      const double e = expected[f] / total;
      EXPECT_NEAR(mu[size_t(f)], e, 0.005 * e + 1e-9) << "face " << f;
      if (e == 0.0) {
        EXPECT_EQ(mu[size_t(f)], 0.0) << "face " << f << " lies below the horizon";
      }
      worst_wrong = std::max(worst_wrong, std::abs(wrong[size_t(f)] - e));
    }
    EXPECT_GT(worst_wrong, 0.05) << "the test cannot tell a face weight without I_f";
  }
}

// Light sampling alone (no BSDF sampling to cover for it): the cube-balanced estimate of
// the irradiance at each one-sided receiver matches the lat-long table's (both unbiased, on
// the same interpolated map) within their combined noise.
TEST(CubeBalancedSampler, LightSamplingAloneAgreesWithTheLatLongTable) {
  const EnvironmentMap env(sun_sky_map(128), 1.0f, Mat3(1.0f));
  const CubeEnvironment cube(env, 32);
  const int samples = 100000;
  for (const CubeReceiver& r : receivers()) {
    if (r.two_sided) continue;
    double sum[2] = {0, 0}, sum_sq[2] = {0, 0};
    Rng rng(60, 0);
    for (int k = 0; k < samples; ++k) {
      float pdf = 0.0f;
      const auto w = sample_cube_balanced(cube, r, rng.uniform2(), &pdf);
      const double cube_value =
          w ? double(luminance(env.radiance(*w))) * std::max(0.0f, glm::dot(*w, r.normal)) / pdf
            : 0.0;
      const Vec3 v = env.sample_direction(rng.uniform2(), &pdf);
      const double table_value = pdf > 0.0f ? double(luminance(env.radiance(v))) *
                                                  std::max(0.0f, glm::dot(v, r.normal)) / pdf
                                            : 0.0;
      sum[0] += cube_value;
      sum_sq[0] += cube_value * cube_value;
      sum[1] += table_value;
      sum_sq[1] += table_value * table_value;
    }
    double mean[2], se[2];
    for (int s = 0; s < 2; ++s) {
      mean[s] = sum[s] / samples;
      se[s] = std::sqrt(std::max(sum_sq[s] / samples - mean[s] * mean[s], 0.0) / samples);
    }
    EXPECT_NEAR(mean[0], mean[1], 4.0 * std::hypot(se[0], se[1]))
        << "normal " << r.normal.x << " " << r.normal.y << " " << r.normal.z;
  }
}

namespace {

// A large diffuse floor (facing up) under `environment`, seen from above.
std::unique_ptr<Scene> floor_under(EnvironmentDesc environment, const Rgb& albedo) {
  SceneDescription d;
  d.source = "cube-env-floor";
  const int m = test::add_material(d, make_lambertian(albedo));
  test::add_quad(d, Vec3(-100, 0, -100), Vec3(-100, 0, 100), Vec3(100, 0, 100), Vec3(100, 0, -100),
                 m);
  d.environment = std::move(environment);
  d.camera = test::camera_at(Vec3(0, 2, 0), Vec3(0.1f, 0, 0.1f), 16, Vec3(0, 0, 1));
  return Scene::build(std::move(d));
}

struct PixelMean {
  double mean = 0.0, standard_error = 0.0;
};

PixelMean green_mean(const Image& image) {
  double sum = 0.0, sum_sq = 0.0;
  for (const Rgb& p : image.pixels) {
    sum += p[1];
    sum_sq += double(p[1]) * p[1];
  }
  const double n = double(image.pixels.size()), mean = sum / n;
  return {mean, std::sqrt(std::max(sum_sq / n - mean * mean, 0.0) / n)};
}

Image render(const Integrator& integrator, const Scene& scene, EnvSampler sampler, int spp,
             MisHeuristic mis = MisHeuristic::Balance) {
  RenderSettings s;
  s.spp = spp;
  s.progress = false;
  s.mis = mis;
  s.env_sampler = sampler;
  ProgressReporter progress(false);
  return integrator.render(scene, s, progress).image;
}

}  // namespace

// A constant sky of radiance L over a white-ish floor: the floor's radiance is albedo L
// (irradiance pi L), through direct lighting and path tracing with the cube-balanced sampler
// (the path tracer's BSDF-sampled rays that find the sky weigh against the previous
// vertex's cube pdf).
TEST(CubeBalancedSampler, ConstantSkyRendersAlbedoTimesRadiance) {
  EnvironmentDesc sky;
  sky.kind = EnvironmentDesc::Kind::Constant;
  sky.radiance = Rgb(2.0f);
  const Rgb albedo(0.5f);
  const auto scene = floor_under(sky, albedo);
  const PathTracer pt;
  const DirectIntegrator direct;
  for (const Integrator* integrator : std::initializer_list<const Integrator*>{&direct, &pt}) {
    const PixelMean m = green_mean(render(*integrator, *scene, EnvSampler::CubeBalanced, 16));
    EXPECT_NEAR(m.mean, 1.0, 5.0 * m.standard_error + 1e-3) << integrator->name();
  }
}

// The sun-and-sky floor: direct lighting and path tracing with the cube-balanced sampler
// agree with direct lighting by the lat-long table, under the balance and the power
// heuristics and the second-order mixture.
TEST(CubeBalancedSampler, SunSkyFloorAgreesWithTheLatLongTable) {
  EnvironmentDesc sky;
  sky.kind = EnvironmentDesc::Kind::Map;
  sky.map = sun_sky_map(128);
  const auto scene = floor_under(sky, Rgb(0.5f));
  const DirectIntegrator direct;
  const PathTracer pt;
  const PixelMean reference = green_mean(render(direct, *scene, EnvSampler::LatLong, 64));
  struct Case {
    const Integrator* integrator;
    MisHeuristic mis;
  };
  for (const Case& c :
       {Case{&direct, MisHeuristic::Balance}, Case{&direct, MisHeuristic::Power},
        Case{&direct, MisHeuristic::SecondOrder}, Case{&pt, MisHeuristic::Balance}}) {
    const PixelMean m =
        green_mean(render(*c.integrator, *scene, EnvSampler::CubeBalanced, 32, c.mis));
    EXPECT_NEAR(m.mean, reference.mean,
                5.0 * std::hypot(m.standard_error, reference.standard_error))
        << c.integrator->name() << " " << to_string(c.mis);
  }
}

// The receiver Eq. 3.4 is evaluated for: the shading normal turned to the side the light
// leaves towards (a two-sided floor seen from its back must get the faces above it), and
// both hemispheres for a BSDF that transmits. Either mistake would stay unbiased (BSDF
// sampling covers what the faces miss), only slower, so it is checked here directly.
TEST(CubeBalancedSampler, ReceiverFacesTheSideLightLeavesTowards) {
  for (const bool transmits : {false, true}) {
    SceneDescription d;
    d.source = "cube-env-receiver";
    const int m = test::add_material(d, transmits ? make_diffuse_transmitter(Rgb(0.5f))
                                                  : make_two_sided(make_lambertian(Rgb(0.5f))));
    // Wound so that the geometric normal points down, away from the camera above.
    test::add_quad(d, Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(1, 0, 1), Vec3(-1, 0, 1), m);
    d.environment.kind = EnvironmentDesc::Kind::Constant;
    d.environment.radiance = Rgb(1.0f);
    d.camera = test::camera_at(Vec3(0, 2, 0), Vec3(0.1f, 0, 0.1f), 16, Vec3(0, 0, 1));
    const auto scene = Scene::build(std::move(d));
    SurfaceHit hit;
    ASSERT_TRUE(scene->intersect(Ray{Vec3(0.1f, 2, 0.1f), Vec3(0, -1, 0)}, hit));
    const Vec3 wo(0, 1, 0);
    const EnvironmentSampling s = environment_sampling(*scene, EnvSampler::CubeBalanced, hit, wo);
    ASSERT_NE(s.cube, nullptr);
    EXPECT_GT(glm::dot(s.receiver.normal, wo), 0.99f) << "shading normal " << hit.shading_normal.y;
    EXPECT_EQ(s.receiver.two_sided, transmits);
    const auto mu = cube_face_weights(*s.cube, s.receiver);
    EXPECT_GT(mu[2], 0.0) << "the face above";
    if (!transmits) {
      EXPECT_EQ(mu[3], 0.0) << "the face below a one-sided receiver";
    } else {
      EXPECT_GT(mu[3], 0.0) << "the face below a transmitting receiver";
    }
    EXPECT_EQ(environment_sampling(*scene, EnvSampler::LatLong, hit, wo).cube, nullptr);
  }
}
