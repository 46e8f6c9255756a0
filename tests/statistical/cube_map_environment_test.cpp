// Cube-map environments (scene/cube_map_environment.h): the faces and their orientation as
// OpenGL's cube-map selection gives them, the sampling density against its histogram, a
// cube map resampled from a lat-long sky rendering as the sky does, and the JSON scene's
// "cubemap" environment with its one-line errors.
#include "emlt/scene/cube_map_environment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "emlt/core/error.h"
#include "emlt/core/rng.h"
#include "emlt/core/warp.h"
#include "emlt/integrators/direct_integrator.h"
#include "emlt/run/progress.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

std::array<Image, 6> constant_faces(const std::array<Rgb, 6>& colours, int n) {
  std::array<Image, 6> faces;
  for (int f = 0; f < 6; ++f) faces[size_t(f)] = Image(n, n, colours[size_t(f)]);
  return faces;
}

// Face f's texel (x, y) of a 2 x 2 map holds (f, x, y) + 1, so a lookup at a texel's centre
// says which texel it found.
std::array<Image, 6> labelled_faces() {
  std::array<Image, 6> faces;
  for (int f = 0; f < 6; ++f) {
    faces[size_t(f)] = Image(2, 2);
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) faces[size_t(f)].at(x, y) = Rgb(float(f + 1), float(x + 1), float(y + 1));
  }
  return faces;
}

// The sky of cube_environment_test.cpp: radiance 1 and a sun lobe 45 degrees up.
const Vec3 kSun = glm::normalize(Vec3(0.6f, 1.0f, -0.8f));
Rgb sun_sky(const Vec3& w) {
  const float lobe = std::pow(std::max(0.0f, glm::dot(w, kSun)), 100.0f);
  return Rgb(1.0f) + 1000.0f * lobe * Rgb(1.0f, 0.9f, 0.7f);
}

// A cube face's texel centre as a direction, by OpenGL's rule inverted (written out per face
// here, apart from the implementation's selection).
Vec3 gl_texel_direction(int face, int x, int y, int n) {
  const float sc = 2.0f * (x + 0.5f) / n - 1.0f, tc = 2.0f * (y + 0.5f) / n - 1.0f;
  switch (face) {
    case 0: return glm::normalize(Vec3(1.0f, -tc, -sc));
    case 1: return glm::normalize(Vec3(-1.0f, -tc, sc));
    case 2: return glm::normalize(Vec3(sc, 1.0f, tc));
    case 3: return glm::normalize(Vec3(sc, -1.0f, -tc));
    case 4: return glm::normalize(Vec3(sc, -tc, 1.0f));
    default: return glm::normalize(Vec3(-sc, -tc, -1.0f));
  }
}

std::array<Image, 6> sun_sky_faces(int n) {
  std::array<Image, 6> faces;
  for (int f = 0; f < 6; ++f) {
    faces[size_t(f)] = Image(n, n);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) faces[size_t(f)].at(x, y) = sun_sky(gl_texel_direction(f, x, y, n));
  }
  return faces;
}

struct PixelMean {
  double mean = 0.0, standard_error = 0.0;
};

// The green channel's mean over the image of a large diffuse floor of albedo 1/2 under
// `environment`, by direct lighting.
PixelMean floor_mean(EnvironmentDesc environment, int spp, EnvSampler sampler = EnvSampler::LatLong) {
  SceneDescription d;
  d.source = "cube-map-floor";
  const int m = test::add_material(d, make_lambertian(Rgb(0.5f)));
  test::add_quad(d, Vec3(-100, 0, -100), Vec3(-100, 0, 100), Vec3(100, 0, 100), Vec3(100, 0, -100), m);
  d.environment = std::move(environment);
  d.camera = test::camera_at(Vec3(0, 2, 0), Vec3(0.1f, 0, 0.1f), 16, Vec3(0, 0, 1));
  const auto scene = Scene::build(std::move(d));
  RenderSettings s;
  s.spp = spp;
  s.progress = false;
  s.env_sampler = sampler;
  ProgressReporter progress(false);
  const Image image = DirectIntegrator().render(*scene, s, progress).image;
  double sum = 0.0, sum_sq = 0.0;
  for (const Rgb& p : image.pixels) {
    sum += p[1];
    sum_sq += double(p[1]) * p[1];
  }
  const double n = double(image.pixels.size()), mean = sum / n;
  return {mean, std::sqrt(std::max(sum_sq / n - mean * mean, 0.0) / n)};
}

}  // namespace

// Each axis looks at its own face, in the order +x, -x, +y, -y, +z, -z, and within a face the
// texel OpenGL's table gives: on a 2 x 2 map, the direction through each texel's centre
// (inverted by hand above) reads exactly that texel. A rotation turns the lookup.
TEST(CubeMapEnvironment, FacesAndTexelsFollowOpenGLSelection) {
  const CubeMapEnvironment axes(
      constant_faces({Rgb(1, 0, 0), Rgb(2, 0, 0), Rgb(3, 0, 0), Rgb(4, 0, 0), Rgb(5, 0, 0), Rgb(6, 0, 0)}, 4),
      1.0f, Mat3(1.0f));
  const Vec3 axis[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int f = 0; f < 6; ++f) EXPECT_EQ(axes.radiance(axis[f]).x, float(f + 1)) << "face " << f;

  const CubeMapEnvironment labelled(labelled_faces(), 1.0f, Mat3(1.0f));
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) {
        const Rgb found = labelled.radiance(gl_texel_direction(f, x, y, 2));
        EXPECT_NEAR(found.x, float(f + 1), 1e-5f) << "face " << f << " texel " << x << "," << y;
        EXPECT_NEAR(found.y, float(x + 1), 1e-5f) << "face " << f << " texel " << x << "," << y;
        EXPECT_NEAR(found.z, float(y + 1), 1e-5f) << "face " << f << " texel " << x << "," << y;
      }

  // A quarter turn about y takes map direction +x to world -z: world -z now sees face +x.
  const Mat3 quarter(glm::rotate(Mat4(1.0f), glm::radians(90.0f), Vec3(0, 1, 0)));
  const CubeMapEnvironment turned(
      constant_faces({Rgb(1, 0, 0), Rgb(2, 0, 0), Rgb(3, 0, 0), Rgb(4, 0, 0), Rgb(5, 0, 0), Rgb(6, 0, 0)}, 4),
      2.0f, quarter);
  EXPECT_EQ(turned.radiance(quarter * Vec3(1, 0, 0)).x, 2.0f);
  EXPECT_NEAR((quarter * Vec3(1, 0, 0)).z, -1.0f, 1e-6f);
}

// The sampler draws what pdf_direction says: chi-square over cells of the sphere (8 x 8 per
// cube face, in world space, under a rotation), against the density integrated over each
// cell by a fine quadrature; the density integrates to one. The face's probability left out
// of the density (a plausible slip) fails both.
TEST(CubeMapEnvironment, SamplingDensityMatchesItsHistogram) {
  const Mat3 tilt(glm::rotate(Mat4(1.0f), glm::radians(30.0f), glm::normalize(Vec3(1, 2, 0))));
  const CubeMapEnvironment env(sun_sky_faces(16), 1.0f, tilt);
  const int cells = 8, sub = 24;
  const auto cell_of = [&](const Vec3& w) {
    Vec2 uv;
    const int face = CubeEnvironment::face_of(w, &uv);
    const int i = std::clamp(int((uv.x + 1.0f) * 0.5f * cells), 0, cells - 1);
    const int j = std::clamp(int((uv.y + 1.0f) * 0.5f * cells), 0, cells - 1);
    return size_t((face * cells + j) * cells + i);
  };
  // Face probabilities, recovered from the density as the injected slip would drop them.
  std::vector<double> expected(size_t(6 * cells * cells), 0.0), without_face(expected.size(), 0.0);
  double total = 0.0;
  const int n = cells * sub;
  const double area = (2.0 / n) * (2.0 / n);
  for (int f = 0; f < 6; ++f) {
    double face_integral = 0.0;
    std::vector<double> in_face(size_t(cells * cells), 0.0);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec2 uv(float(-1.0 + (i + 0.5) * 2.0 / n), float(-1.0 + (j + 0.5) * 2.0 / n));
        const double jac = std::pow(1.0 + double(uv.x) * uv.x + double(uv.y) * uv.y, -1.5);
        const double p = double(env.pdf_direction(CubeEnvironment::direction(f, uv))) * jac * area;
        in_face[size_t((j / sub) * cells + i / sub)] += p;
        face_integral += p;
      }
    total += face_integral;
    for (size_t c = 0; c < in_face.size(); ++c) {
      expected[size_t(f * cells * cells) + c] = in_face[c];
      without_face[size_t(f * cells * cells) + c] = face_integral > 0.0 ? in_face[c] / face_integral / 6.0 : 0.0;
    }
  }
  EXPECT_NEAR(total, 1.0, 1e-4);

  const int samples = 200000;
  Rng rng(17, 0);
  std::vector<double> observed(expected.size(), 0.0);
  for (int k = 0; k < samples; ++k) {
    float pdf = 0.0f;
    const Vec3 w = env.sample_direction(rng.uniform2(), &pdf);
    ASSERT_GT(pdf, 0.0f);
    ASSERT_EQ(pdf, env.pdf_direction(w));
    observed[cell_of(w)] += 1.0;
  }
  for (double& e : expected) e *= samples;
  for (double& e : without_face) e *= samples;
  const auto good = test::chi_square_test(observed, expected);
  EXPECT_GT(good.p_value, 1e-3) << "chi2 " << good.statistic << " dof " << good.degrees_of_freedom;
  const auto bad = test::chi_square_test(observed, without_face);
  EXPECT_LT(bad.p_value, 1e-9) << "the test cannot tell a density without the face's probability";
}

// A cube map made from the sun-and-sky function by OpenGL's rule lights a floor as the same
// sky given as a lat-long map does (the two differ only by resampling, well under the 1 %
// allowed), through the map's own table and through Lu's cube-face sampler. A face order
// or orientation that put the sun elsewhere would change the floor's light by the sun's
// cosine.
TEST(CubeMapEnvironment, ResampledSkyLightsAFloorAsTheLatLongSkyDoes) {
  EnvironmentDesc latlong;
  latlong.kind = EnvironmentDesc::Kind::Map;
  latlong.map = Image(256, 128);
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 256; ++x)
      latlong.map.at(x, y) = sun_sky(latlong_to_direction(Vec2((x + 0.5f) / 256.0f, (y + 0.5f) / 128.0f)));
  const PixelMean reference = floor_mean(latlong, 64);

  EnvironmentDesc cube;
  cube.kind = EnvironmentDesc::Kind::CubeMap;
  for (Image& face : sun_sky_faces(64)) cube.cube_faces.push_back(std::move(face));
  for (const EnvSampler sampler : {EnvSampler::LatLong, EnvSampler::CubeBalanced}) {
    const PixelMean m = floor_mean(cube, 32, sampler);
    EXPECT_NEAR(m.mean / reference.mean, 1.0,
                0.01 + 5.0 * std::hypot(m.standard_error, reference.standard_error) / reference.mean)
        << (sampler == EnvSampler::LatLong ? "the map's table" : "cube-balanced");
  }
}

// The JSON scene's "cubemap": six files (+x, -x, +y, -y, +z, -z) of a constant sky light the
// floor to albedo x radiance; a wrong count, a face that is not square and faces of two sizes
// are one-line errors naming the file.
TEST(CubeMapEnvironment, JsonSceneReadsSixFacesAndNamesABadOne) {
  const auto dir = std::filesystem::temp_directory_path() / "emlt-cubemap-test";
  std::filesystem::create_directories(dir);
  const char* names[6] = {"px.pfm", "nx.pfm", "py.pfm", "ny.pfm", "pz.pfm", "nz.pfm"};
  for (const char* name : names) write_image((dir / name).string(), Image(4, 4, Rgb(2.0f)));
  write_image((dir / "oblong.pfm").string(), Image(4, 2, Rgb(2.0f)));
  write_image((dir / "big.pfm").string(), Image(8, 8, Rgb(2.0f)));
  const auto scene_with = [&](const std::string& faces, const std::string& file) {
    const std::string path = (dir / file).string();
    std::ofstream(path) << R"({"camera": {"lookat": {"origin": [0, 2, 0], "target": [0.1, 0, 0.1], "up": [0, 0, 1]},
        "fov": 16, "width": 8, "height": 8},
      "materials": {"white": {"type": "diffuse", "reflectance": 0.5}},
      "shapes": [{"type": "rectangle", "material": "white",
                  "transform": [{"rotate": {"axis": [1, 0, 0], "angle": -90}}, {"scale": 100}]}],
      "environment": {"type": "cubemap", "faces": [)" << faces << R"(]}})";
    return path;
  };
  const auto scene = Scene::build(load_scene_description(
      scene_with(R"("px.pfm", "nx.pfm", "py.pfm", "ny.pfm", "pz.pfm", "nz.pfm")", "good.json")));
  ASSERT_TRUE(scene->environment());
  EXPECT_NEAR(scene->environment()->radiance(glm::normalize(Vec3(0.3f, 1.0f, -0.2f))).y, 2.0f, 1e-6f);
  RenderSettings s;
  s.spp = 32;
  s.progress = false;
  ProgressReporter progress(false);
  const Image image = DirectIntegrator().render(*scene, s, progress).image;
  double sum = 0.0;
  for (const Rgb& p : image.pixels) sum += p[1];
  EXPECT_NEAR(sum / double(image.pixels.size()), 1.0, 0.02);

  const auto error_of = [&](const std::string& faces, const std::string& file) {
    try {
      Scene::build(load_scene_description(scene_with(faces, file)));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(loaded)");
  };
  const std::string five = error_of(R"("px.pfm", "nx.pfm", "py.pfm", "ny.pfm", "pz.pfm")", "five.json");
  EXPECT_NE(five.find("five.json"), std::string::npos) << five;
  EXPECT_NE(five.find("six file names"), std::string::npos) << five;
  const std::string oblong =
      error_of(R"("px.pfm", "nx.pfm", "oblong.pfm", "ny.pfm", "pz.pfm", "nz.pfm")", "oblong.json");
  EXPECT_NE(oblong.find("oblong.pfm: a cube map face must be square"), std::string::npos) << oblong;
  const std::string sizes =
      error_of(R"("px.pfm", "nx.pfm", "py.pfm", "ny.pfm", "pz.pfm", "big.pfm")", "sizes.json");
  EXPECT_NE(sizes.find("big.pfm: the cube map's faces differ in size"), std::string::npos) << sizes;
  const std::string missing =
      error_of(R"("px.pfm", "nx.pfm", "py.pfm", "ny.pfm", "pz.pfm", "gone.pfm")", "missing.json");
  EXPECT_NE(missing.find("gone.pfm' not found"), std::string::npos) << missing;
  EXPECT_EQ(std::count(missing.begin(), missing.end(), '\n'), 0) << missing;
  std::filesystem::remove_all(dir);
}
