#include <gtest/gtest.h>

#include "emlt/core/rng.h"
#include "emlt/core/warp.h"
#include "emlt/scene/camera.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

CameraDesc test_camera(float aperture, int w = 64, int h = 48) {
  CameraDesc d;
  d.to_world = look_at_matrix(Vec3(1, 2, -5), Vec3(0.5f, 1.5f, 0), Vec3(0, 1, 0));
  d.fov_degrees = 40.0f;
  d.width = w;
  d.height = h;
  d.aperture_radius = aperture;
  d.focus_distance = 4.0f;
  return d;
}

}  // namespace

class CameraTest : public ::testing::TestWithParam<float> {};

TEST_P(CameraTest, RasterPositionInvertsGenerateRay) {
  const Camera camera(test_camera(GetParam()));
  Rng rng(1, 0);
  for (int i = 0; i < 2000; ++i) {
    const Vec2 raster(rng.uniform() * 64.0f, rng.uniform() * 48.0f);
    const Ray ray = camera.generate_ray(raster, rng.uniform2());
    const auto back = camera.raster_position(ray.origin, ray.direction);
    ASSERT_TRUE(back.has_value());
    EXPECT_NEAR(back->x, raster.x, 2e-3f);
    EXPECT_NEAR(back->y, raster.y, 2e-3f);
  }
}

TEST_P(CameraTest, DirectionPdfIntegratesToOneOverTheSphere) {
  // E over uniform sphere directions of pdf_direction / uniform_pdf must be 1.
  const Camera camera(test_camera(GetParam()));
  Rng rng(2, 0);
  double sum = 0.0, sum2 = 0.0;
  const int n = 400000;
  for (int i = 0; i < n; ++i) {
    const Vec3 w = square_to_uniform_sphere(rng.uniform2());
    float pdf_pos = 0.0f, pdf_dir = 0.0f;
    camera.pdf_emission(w, &pdf_pos, &pdf_dir);
    // Only directions that land on the film are ever generated.
    const double v = camera.raster_position(camera.position(), w) ? pdf_dir / uniform_sphere_pdf() : 0.0;
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, 1.0, 4.0 * se + 1e-3);
}

TEST_P(CameraTest, GeneratedRaysHitPixelsUniformly) {
  // Histogram of raster positions recovered from generated rays (lens centre projection).
  const Camera camera(test_camera(GetParam(), 16, 12));
  Rng rng(3, 0);
  std::vector<double> counts(16 * 12, 0.0);
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const Ray ray = camera.generate_ray(Vec2(rng.uniform() * 16.0f, rng.uniform() * 12.0f), rng.uniform2());
    const auto r = camera.raster_position(ray.origin, ray.direction);
    ASSERT_TRUE(r.has_value());
    counts[size_t(int(r->y) * 16 + int(r->x))] += 1.0;
  }
  const std::vector<double> expected(counts.size(), double(n) / double(counts.size()));
  EXPECT_GT(test::chi_square_test(counts, expected).p_value, 1e-3);
}

TEST_P(CameraTest, SampleDirectIsConsistentWithImportanceAndPdf) {
  const Camera camera(test_camera(GetParam()));
  Rng rng(4, 0);
  int found = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 ref = Vec3(0.5f, 1.5f, 0) + 2.0f * (rng.uniform2().x - 0.5f) * Vec3(1, 0, 0) +
                     2.0f * (rng.uniform() - 0.5f) * Vec3(0, 1, 0);
    const auto s = camera.sample_direct(ref, rng.uniform2());
    if (!s) continue;
    ++found;
    const Ray ray{s->lens_point, -s->wi};
    EXPECT_NEAR(s->importance.x, camera.importance(s->lens_point, -s->wi), 1e-4f * s->importance.x);
    const auto raster = camera.raster_position(ray.origin, ray.direction);
    ASSERT_TRUE(raster.has_value());
    EXPECT_NEAR(raster->x, s->raster.x, 1e-2f);
    // The solid-angle pdf at ref equals the lens area density converted by d^2 / cos.
    float pdf_pos = 0.0f, pdf_dir = 0.0f;
    camera.pdf_emission(-s->wi, &pdf_pos, &pdf_dir);
    const float cos_lens = std::abs(glm::dot(camera.forward(), s->wi));
    EXPECT_NEAR(s->pdf, pdf_pos * s->distance * s->distance / cos_lens, 1e-3f * s->pdf);
  }
  EXPECT_GT(found, 1000);
}

INSTANTIATE_TEST_SUITE_P(PinholeAndThinLens, CameraTest, ::testing::Values(0.0f, 0.2f));

TEST(Camera, ImageIsNotMirrored) {
  // Looking down +z from the origin with up +y, world +x must appear on the image's right
  // exactly when the camera frame is right-handed as Mitsuba's lookat makes it.
  CameraDesc d;
  d.to_world = look_at_matrix(Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(0, 1, 0));
  d.width = d.height = 100;
  const Camera camera(d);
  const auto right = camera.raster_position(Vec3(0), glm::normalize(Vec3(-0.1f, 0, 1)));
  const auto up = camera.raster_position(Vec3(0), glm::normalize(Vec3(0, 0.1f, 1)));
  ASSERT_TRUE(right && up);
  // Mitsuba's lookat: camera +x = cross(up, dir) = world -x here, i.e. image left.
  EXPECT_GT(right->x, 50.0f);
  EXPECT_LT(up->y, 50.0f);
}
