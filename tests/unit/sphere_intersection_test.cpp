// Ray-sphere intersection: the root finding itself (sphere_intersection.h) on the cases
// where float arithmetic goes wrong, and Scene's use of it on both of its paths (a few
// spheres tested directly, more in Embree's BVH as a user geometry): segment limits, rays
// from inside, ordering against triangles, and alpha masks.
#include "emlt/scene/sphere_intersection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "emlt/scene/shape_builders.h"
#include "emlt/scene/texture.h"

using namespace emlt;

namespace {

TEST(SphereRoots, BothRootsOfASimpleChord) {
  SphereRoots roots;
  ASSERT_TRUE(sphere_roots(Vec3(1, 2, 3), 2.0f, Vec3(1, 2, -7), Vec3(0, 0, 1), &roots));
  EXPECT_FLOAT_EQ(roots.near, 8.0f);
  EXPECT_FLOAT_EQ(roots.far, 12.0f);
  // From the centre: one root behind the origin, one ahead.
  ASSERT_TRUE(sphere_roots(Vec3(1, 2, 3), 2.0f, Vec3(1, 2, 3), Vec3(0, 1, 0), &roots));
  EXPECT_FLOAT_EQ(roots.near, -2.0f);
  EXPECT_FLOAT_EQ(roots.far, 2.0f);
  // An unnormalised direction scales t (Embree does not require unit directions).
  ASSERT_TRUE(sphere_roots(Vec3(0), 1.0f, Vec3(0, 0, -5), Vec3(0, 0, 2), &roots));
  EXPECT_FLOAT_EQ(roots.near, 2.0f);
  EXPECT_FLOAT_EQ(roots.far, 3.0f);
  EXPECT_FALSE(sphere_roots(Vec3(0), 1.0f, Vec3(0, 1.01f, -5), Vec3(0, 0, 1), &roots));
  EXPECT_FALSE(sphere_roots(Vec3(0), 1.0f, Vec3(0, 0, -5), Vec3(0), &roots));
}

TEST(SphereRoots, FarAwayRayKeepsTheChord) {
  // 10^4 radii away, b^2/4 and ac agree in all of a float's digits (1e8 - 0.75 rounds to
  // 1e8): the textbook discriminant is 0 and the chord collapses to a point.
  SphereRoots roots;
  ASSERT_TRUE(sphere_roots(Vec3(0), 1.0f, Vec3(0.5f, 0.0f, -1e4f), Vec3(0, 0, 1), &roots));
  const float half_chord = std::sqrt(0.75f);
  EXPECT_NEAR(roots.near, 1e4f - half_chord, 3e-3f);
  EXPECT_NEAR(roots.far, 1e4f + half_chord, 3e-3f);
}

TEST(SphereRoots, GrazingRayKeepsTheChord) {
  // 0.1 % inside the rim, 100 radii away: the discriminant (0.002) is below the float
  // spacing of b^2/4 (about 0.001 at 1e4) in the textbook form.
  SphereRoots roots;
  ASSERT_TRUE(sphere_roots(Vec3(0), 1.0f, Vec3(0.999f, 0.0f, -100.0f), Vec3(0, 0, 1), &roots));
  const float expected_chord = 2.0f * std::sqrt(1.0f - 0.999f * 0.999f);  // 0.0894
  EXPECT_NEAR(roots.far - roots.near, expected_chord, 1e-4f);
  EXPECT_NEAR(0.5f * (roots.near + roots.far), 100.0f, 1e-4f);
}

// A ball of radius 1 at the origin (seen along +z from z = -5 by most tests), lit by a
// constant environment, and `decoys` small spheres off every test ray: more than
// Scene::kMaxDirectSpheres spheres move all of them into Embree's BVH.
SceneDescription ball_scene(size_t decoys, float opacity = 1.0f) {
  SceneDescription desc;
  desc.source = "sphere-test";
  desc.materials.push_back({"grey", make_lambertian(Rgb(0.5f))});
  const bool masked = opacity < 1.0f;
  if (masked)
    desc.materials.push_back(
        MaterialDesc("masked", make_lambertian(Rgb(0.5f)), make_constant_texture(Rgb(opacity))));
  desc.camera.to_world = look_at_matrix(Vec3(0, 0, -20), Vec3(0, 0, 0), Vec3(0, 1, 0));
  desc.camera.width = desc.camera.height = 8;
  desc.environment.kind = EnvironmentDesc::Kind::Constant;
  desc.environment.radiance = Rgb(1.0f);
  desc.spheres.push_back({"ball", Vec3(0), 1.0f, masked ? 1 : 0, Rgb(0.0f), false});
  for (size_t i = 0; i < decoys; ++i)
    desc.spheres.push_back(
        {"decoy", Vec3(100.0f + 3.0f * float(i), 100.0f, 100.0f), 0.5f, 0, Rgb(0.0f), false});
  return desc;
}

class SceneSphere : public ::testing::TestWithParam<bool> {
 protected:
  // The parameter: whether the spheres go into the BVH.
  size_t decoys() const { return GetParam() ? Scene::kMaxDirectSpheres : 0; }
};

TEST_P(SceneSphere, SegmentLimitsPickTheRootOrNone) {
  const auto scene = Scene::build(ball_scene(decoys()));
  const Vec3 origin(0, 0, -5), forward(0, 0, 1);
  struct Case {
    float tmin, tmax;
    float expected;  // 0: no hit
  };
  // Entry at t = 4, exit at t = 6.
  for (const Case& c :
       {Case{0.0f, 3.9f, 0.0f}, Case{0.0f, 4.1f, 4.0f}, Case{0.0f, kInfinity, 4.0f},
        Case{4.5f, kInfinity, 6.0f}, Case{4.5f, 5.9f, 0.0f}, Case{6.5f, kInfinity, 0.0f}}) {
    const Ray ray{origin, forward, c.tmin, c.tmax};
    SurfaceHit hit;
    const bool found = scene->intersect(ray, hit);
    EXPECT_EQ(found, c.expected > 0.0f) << "segment [" << c.tmin << ", " << c.tmax << "]";
    EXPECT_EQ(scene->occluded(ray), c.expected > 0.0f)
        << "segment [" << c.tmin << ", " << c.tmax << "]";
    if (found && c.expected > 0.0f) {
      EXPECT_NEAR(hit.t, c.expected, 1e-4f);
      EXPECT_NEAR(hit.position.z, c.expected - 5.0f, 1e-4f);
    }
  }
}

TEST_P(SceneSphere, RaysFromInsideHitTheFarSide) {
  // Refraction into glass starts a ray inside the sphere: the root behind it is no hit.
  const auto scene = Scene::build(ball_scene(decoys()));
  for (const Vec3& start : {Vec3(0), Vec3(0.3f, -0.2f, 0.5f)}) {
    for (const Vec3& direction : {Vec3(0, 0, 1), glm::normalize(Vec3(1, -1, 0.5f))}) {
      SurfaceHit hit;
      ASSERT_TRUE(scene->intersect(Ray{start, direction}, hit));
      EXPECT_NEAR(glm::length(hit.position), 1.0f, 1e-5f);
      EXPECT_GT(glm::dot(hit.position - start, direction), 0.0f);
      EXPECT_NEAR(glm::dot(hit.geometric_normal, hit.position), 1.0f, 1e-5f);  // outward
      EXPECT_TRUE(scene->occluded(Ray{start, direction, 0.0f, hit.t * 1.001f}));
      EXPECT_FALSE(scene->occluded(Ray{start, direction, 0.0f, hit.t * 0.999f}));
    }
  }
}

TEST_P(SceneSphere, NearestOfSphereAndTriangleWins) {
  for (const float wall_z : {-4.5f, 0.5f, 3.0f}) {  // before the sphere, inside it, behind it
    SceneDescription desc = ball_scene(decoys());
    MeshDesc wall = make_rectangle_mesh(glm::translate(Mat4(1.0f), Vec3(0, 0, wall_z)) *
                                        glm::scale(Mat4(1.0f), Vec3(3.0f)));
    wall.name = "wall";
    wall.material = 0;
    desc.meshes.push_back(wall);
    const auto scene = Scene::build(desc);
    SurfaceHit hit;
    ASSERT_TRUE(scene->intersect(Ray{Vec3(0, 0, -5), Vec3(0, 0, 1)}, hit));
    const float expected = std::min(wall_z + 5.0f, 4.0f);
    EXPECT_NEAR(hit.t, expected, 1e-4f) << "wall at z = " << wall_z;
    // A segment starting inside the sphere, past the walls at -4.5 and 0.5: the exit at
    // t = 6 comes before the wall at 3.
    ASSERT_TRUE(scene->intersect(Ray{Vec3(0, 0, -5), Vec3(0, 0, 1), 5.6f, kInfinity}, hit));
    EXPECT_NEAR(hit.t, 6.0f, 1e-4f) << "wall at z = " << wall_z;
  }
}

TEST_P(SceneSphere, TransparentMaskLetsRaysThroughBothSides) {
  // Opacity 0: neither the entry nor the exit stops a ray (Mitsuba's mask).
  const auto scene = Scene::build(ball_scene(decoys(), 0.0f));
  for (const Vec3& start : {Vec3(0, 0, -5), Vec3(0)}) {
    const Ray ray{start, Vec3(0, 0, 1)};
    SurfaceHit hit;
    EXPECT_FALSE(scene->intersect(ray, hit));
    EXPECT_FALSE(scene->occluded(ray));
  }
}

TEST_P(SceneSphere, PartialMaskStopsThatFractionAndBothQueriesAgree) {
  // The alpha test hashes the ray, not the hit distance, so a ray that passes the entry
  // passes the exit too: a fraction `opacity` of the rays through the ball stop on it.
  const float opacity = 0.3f;
  const auto scene = Scene::build(ball_scene(decoys(), opacity));
  const int rays = 4000;
  int stopped = 0, disagreements = 0;
  for (int i = 0; i < rays; ++i) {
    const float x = -0.6f + 1.2f * float(i % 63) / 63.0f, y = -0.6f + 1.2f * float(i / 63) / 64.0f;
    const Ray ray{Vec3(x, y, -5.0f), Vec3(0, 0, 1)};
    SurfaceHit hit;
    const bool found = scene->intersect(ray, hit);
    stopped += found;
    disagreements += found != scene->occluded(ray);
  }
  EXPECT_NEAR(double(stopped) / rays, opacity, 4.0 * std::sqrt(0.3 * 0.7 / rays));
  EXPECT_EQ(disagreements, 0);
}

INSTANTIATE_TEST_SUITE_P(DirectAndInBvh, SceneSphere, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& info) {
                           return info.param ? "InBvh" : "Direct";
                         });

}  // namespace
