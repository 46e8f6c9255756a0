// The shading frame of a hit is Mitsuba 0.6's: n the shading normal, s = dp/du made
// orthogonal to n (Gram-Schmidt), t = n x s. Anisotropic BSDFs are oriented by s, so it
// must be dp/du's direction: the parallels of a sphere, the direction of increasing u on a
// mesh with uvs, p1 - p0 on a mesh without.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "emlt/core/frame.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "emlt/scene/shape_builders.h"

using namespace emlt;

namespace {

SceneDescription with_light() {
  SceneDescription desc;
  desc.source = "frame-test";
  desc.materials.push_back({"grey", make_lambertian(Rgb(0.5f))});
  // Material 1 is anisotropic: only such BSDFs make the frame follow dp/du.
  desc.materials.push_back(
      {"brushed", make_rough_conductor(make_constant_texture(Rgb(0.1f)), Rgb(0.2f), Rgb(3.0f),
                                       make_constant_texture(Rgb(1.0f)), MicrofacetType::Ggx,
                                       make_constant_texture(Rgb(0.4f)))});
  desc.camera.to_world = look_at_matrix(Vec3(0, 0, -20), Vec3(0, 0, 0), Vec3(0, 1, 0));
  desc.camera.width = desc.camera.height = 8;
  MeshDesc light = make_rectangle_mesh(glm::translate(Mat4(1.0f), Vec3(0, 100, 0)));
  light.name = "light";
  light.material = 0;
  light.emission = Rgb(1.0f);
  desc.meshes.push_back(light);
  return desc;
}

void expect_orthonormal(const Frame& f) {
  EXPECT_NEAR(glm::length(f.s), 1.0f, 1e-5f);
  EXPECT_NEAR(glm::length(f.t), 1.0f, 1e-5f);
  EXPECT_NEAR(glm::dot(f.s, f.n), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::dot(f.t, f.n), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(f.t - glm::cross(f.n, f.s)), 0.0f, 1e-5f);
}

void expect_near(const Vec3& a, const Vec3& b, float tolerance = 1e-4f) {
  EXPECT_NEAR(glm::length(a - b), 0.0f, tolerance) << a.x << "," << a.y << "," << a.z;
}

}  // namespace

TEST(ShadingFrame, GramSchmidtOfTheTangent) {
  const Vec3 n = glm::normalize(Vec3(0.2f, -0.3f, 0.9f));
  const Frame f(n, Vec3(2.0f, 0.5f, 1.0f));
  expect_orthonormal(f);
  expect_near(f.n, n);
  const Vec3 projected = Vec3(2.0f, 0.5f, 1.0f) - n * glm::dot(n, Vec3(2.0f, 0.5f, 1.0f));
  expect_near(f.s, glm::normalize(projected));
  // A tangent along the normal (or none) leaves the frame of the normal alone.
  const Frame fallback(n, 3.0f * n), from_normal(n);
  expect_near(fallback.s, from_normal.s);
  expect_near(Frame(n, Vec3(0.0f)).s, from_normal.s);
}

TEST(ShadingFrame, SphereFollowsItsParallels) {
  SceneDescription desc = with_light();
  desc.spheres.push_back({"ball", Vec3(1, 2, 3), 2.0f, 1, Rgb(0.0f), false});
  const auto scene = Scene::build(desc);
  for (const Vec3 target : {Vec3(1.5f, 2.5f, 3.0f), Vec3(0.2f, 1.1f, 3.0f), Vec3(1.0f, 3.9f, 3.0f)}) {
    SurfaceHit hit;
    ASSERT_TRUE(scene->intersect(Ray{Vec3(target.x, target.y, -10.0f), Vec3(0, 0, 1)}, hit));
    expect_orthonormal(hit.shading);
    const Vec3 n = glm::normalize(hit.position - Vec3(1, 2, 3));
    expect_near(hit.shading.n, n);
    // dp/du = 2 pi r (-n_y, n_x, 0) (u the longitude about z, as in Mitsuba).
    expect_near(hit.shading.s, glm::normalize(Vec3(-n.y, n.x, 0.0f)));
  }
}

TEST(ShadingFrame, MeshWithUvsFollowsIncreasingU) {
  SceneDescription desc = with_light();
  MeshDesc quad;
  quad.name = "quad";
  quad.material = 1;
  quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  quad.indices = {0, 1, 2, 0, 2, 3};
  // u grows along +y, v along -x: the frame's s must point along +y whatever the winding.
  for (const Vec3& p : quad.positions) quad.uvs.push_back(Vec2(0.5f * (p.y + 1), 0.5f * (1 - p.x)));
  // Tilted vertex normals: s stays in the plane of dp/du and the shading normal.
  const Vec3 tilted = glm::normalize(Vec3(0.3f, 0.4f, -1.0f));
  quad.normals.assign(4, tilted);
  desc.meshes.push_back(quad);
  const auto scene = Scene::build(desc);
  for (const Vec2 xy : {Vec2(0.5f, -0.5f), Vec2(-0.5f, 0.5f)}) {
    SurfaceHit hit;
    ASSERT_TRUE(scene->intersect(Ray{Vec3(xy, 5.0f), Vec3(0, 0, -1)}, hit));
    expect_orthonormal(hit.shading);
    expect_near(hit.shading.n, tilted);
    const Vec3 dpdu(0, 2, 0);
    expect_near(hit.shading.s, glm::normalize(dpdu - tilted * glm::dot(tilted, dpdu)));
  }
}

TEST(ShadingFrame, MeshWithoutUvsUsesTheFirstEdge) {
  SceneDescription desc = with_light();
  MeshDesc tri;
  tri.name = "tri";
  tri.material = 1;
  tri.positions = {{-1, -1, 0}, {1, 0, 0}, {-1, 1, 0}};
  tri.indices = {0, 1, 2};
  desc.meshes.push_back(tri);
  const auto scene = Scene::build(desc);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(-0.5f, 0.0f, 5.0f), Vec3(0, 0, -1)}, hit));
  expect_orthonormal(hit.shading);
  expect_near(hit.shading.s, glm::normalize(Vec3(2, 1, 0)));  // p1 - p0, as Mitsuba
}

TEST(ShadingFrame, IsotropicBsdfsKeepTheNormalsOwnFrame) {
  // Turning the frame about the normal changes nothing an isotropic BSDF returns, so those
  // keep the normal's own frame (and the random streams of every existing render).
  SceneDescription desc = with_light();
  desc.spheres.push_back({"ball", Vec3(1, 2, 3), 2.0f, 0, Rgb(0.0f), false});
  const auto scene = Scene::build(desc);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(1.5f, 2.5f, -10.0f), Vec3(0, 0, 1)}, hit));
  const Frame own(hit.shading_normal);
  expect_near(hit.shading.s, own.s);
  expect_near(hit.shading.t, own.t);
}
