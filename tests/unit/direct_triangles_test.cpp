// The direct triangle test of small scenes (emlt/scene/direct_triangles.h): watertight on
// shared edges, Embree's conventions for t, u and v, and the same answers as Embree's BVH
// on the repository's Cornell boxes.
#include "emlt/scene/direct_triangles.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "emlt/core/rng.h"
#include "emlt/core/warp.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "emlt/scene/shape_builders.h"
#include "tests/support/test_support.h"

using namespace emlt;

namespace {

#define SKIP_WITHOUT_DIRECT_TRIANGLES() \
  if (!DirectTriangles::available()) GTEST_SKIP() << "this CPU has no AVX2"

// A regular grid of n x n squares in the plane z = 0 over [0, 1]^2, two triangles each,
// every shared edge made of the same two vertices in both triangles (a mesh, as a loader
// builds it). Each square is split along its diagonal from (i, j) to (i + 1, j + 1).
DirectTriangles grid(int n) {
  DirectTriangles set;
  const auto vertex = [n](int i, int j) {
    return Vec3(float(i) / float(n), float(j) / float(n), 0.0f);
  };
  uint32_t primitive = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      set.add(0, primitive++, vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1));
      set.add(0, primitive++, vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1));
    }
  return set;
}

}  // namespace

TEST(DirectTriangles, NoRaySlipsThroughASharedEdgeOrVertex) {
  SKIP_WITHOUT_DIRECT_TRIANGLES();
  // 4 x 4 squares: 32 triangles, four full blocks of lanes. Rays aimed at points exactly on
  // the grid's lines and diagonals (edges shared by two triangles, and vertices shared by up
  // to six), from above and from below, from origins that are not on any axis, so that the
  // shear is a real one.
  const int n = 4;
  const DirectTriangles set = grid(n);
  ASSERT_EQ(set.size(), 32u);
  Rng rng(7, 0);
  int rays = 0;
  for (int k = 1; k < 64; ++k) {  // inside the grid: its outer border is no shared edge
    const float s = float(k) / 64.0f;
    // On the vertical and horizontal lines x = i/n, y = i/n, and on the diagonals y = x + c.
    std::vector<Vec3> targets;
    for (int i = 1; i < n; ++i) {
      targets.push_back(Vec3(float(i) / float(n), s, 0.0f));
      targets.push_back(Vec3(s, float(i) / float(n), 0.0f));
    }
    for (int i = 0; i < n; ++i) {
      const float c = float(i) / float(n);
      if (s + c < 1.0f) targets.push_back(Vec3(s + c, s, 0.0f));
    }
    for (const Vec3& target : targets) {
      for (const float side : {1.0f, -1.0f}) {
        const Vec3 origin(0.3f + 2.0f * rng.uniform(), -0.7f + 2.0f * rng.uniform(), 1.3f * side);
        const Ray ray{origin, glm::normalize(target - origin), 0.0f, kInfinity};
        float tfar = kInfinity;
        DirectTriangleHit hit;
        ASSERT_TRUE(set.nearest(ray, &tfar, &hit))
            << "missed (" << target.x << ", " << target.y << ") from side " << side;
        EXPECT_NEAR(tfar, glm::length(target - origin), 1e-5f);
        ASSERT_TRUE(set.any(ray));
        ++rays;
      }
    }
  }
  EXPECT_GT(rays, 800);
}

TEST(DirectTriangles, FollowsEmbreesConventionsForDistanceAndBarycentrics) {
  SKIP_WITHOUT_DIRECT_TRIANGLES();
  // Nine triangles: one full block and one lane of the next (its seven other lanes are the
  // zero-area padding at the origin, which a ray through the origin must not hit).
  DirectTriangles set;
  for (uint32_t i = 0; i < 8; ++i) {
    const float x = 10.0f + 3.0f * float(i);
    set.add(1, i, Vec3(x, 0, 5), Vec3(x + 2, 0, 5), Vec3(x, 2, 5));
  }
  const Vec3 p0(0, 0, 2), p1(4, 0, 2), p2(0, 4, 2);
  set.add(7, 42, p0, p1, p2);
  ASSERT_EQ(set.size(), 9u);

  // Through the last triangle at barycentrics (u, v) = (0.25, 0.5), from above (front) and
  // from below (back).
  const Vec3 target = 0.25f * p0 + 0.25f * p1 + 0.5f * p2;
  for (const float z : {6.0f, -3.0f}) {
    const Vec3 origin(0.5f, 0.2f, z);
    const Ray ray{origin, glm::normalize(target - origin), 0.0f, kInfinity};
    float tfar = kInfinity;
    DirectTriangleHit hit;
    ASSERT_TRUE(set.nearest(ray, &tfar, &hit)) << "from z = " << z;
    EXPECT_EQ(hit.geometry, 7u);
    EXPECT_EQ(hit.primitive, 42u);
    EXPECT_NEAR(hit.t, glm::length(target - origin), 1e-5f);
    EXPECT_EQ(tfar, hit.t);
    EXPECT_NEAR(hit.u, 0.25f, 1e-6f);  // weight of p1
    EXPECT_NEAR(hit.v, 0.5f, 1e-6f);   // weight of p2
    // The segment ends: a hit at t <= tfar counts, none at or before tmin.
    float shorter = hit.t * (1.0f - 1e-6f);
    EXPECT_FALSE(set.nearest(ray, &shorter, &hit));
    EXPECT_FALSE(set.any(Ray{origin, ray.direction, 0.0f, hit.t * (1.0f - 1e-6f)}));
    EXPECT_TRUE(set.any(Ray{origin, ray.direction, 0.0f, hit.t * (1.0f + 1e-6f)}));
    EXPECT_FALSE(set.any(Ray{origin, ray.direction, hit.t * (1.0f + 1e-6f), kInfinity}));
  }

  // Nearest of two: the triangle of the first block at z = 5 lies behind the last one.
  const Ray down{Vec3(10.5f, 0.5f, 9.0f), Vec3(0, 0, -1), 0.0f, kInfinity};
  float tfar = kInfinity;
  DirectTriangleHit hit;
  ASSERT_TRUE(set.nearest(down, &tfar, &hit));
  EXPECT_EQ(hit.primitive, 0u);
  EXPECT_FLOAT_EQ(hit.t, 4.0f);

  // The padding is at the origin, with zero area: a ray through it meets nothing.
  for (const Vec3& direction : {Vec3(1, 0, 0), Vec3(0, 1, 0), glm::normalize(Vec3(1, -1, 0))}) {
    const Ray through_origin{-3.0f * direction, direction, 0.0f, kInfinity};
    float far = kInfinity;
    EXPECT_FALSE(set.nearest(through_origin, &far, &hit))
        << "hit " << hit.geometry << "/" << hit.primitive << " at " << hit.t;
    EXPECT_FALSE(set.any(through_origin));
  }
}

TEST(DirectTriangles, AgreeWithEmbreesBvhOnTheCornellBoxes) {
  SKIP_WITHOUT_DIRECT_TRIANGLES();
  for (const char* name : {"cornell-box", "cornell-glass"}) {
    const std::string path = test::source_path(std::string("scenes/") + name + "/scene.xml");
    const auto direct = Scene::build(load_scene_description(path, {}));
    const auto bvh = Scene::build(load_scene_description(path, {}),
                                  SceneBuildOptions{.direct_triangles = false});
    ASSERT_TRUE(direct->stats().direct_triangles) << name;
    ASSERT_FALSE(bvh->stats().direct_triangles) << name;
    // Rays from random points inside the scene's bounds in uniform directions (a box's
    // walls, seen from anywhere), and shadow segments along each ray to just short of its
    // hit and just past it.
    Rng rng(11, 0);
    int hits = 0, same_triangle = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 origin = bvh->bounds_center() + 0.5f * bvh->bounds_radius() *
                                                     square_to_uniform_sphere(rng.uniform2()) *
                                                     std::cbrt(rng.uniform());
      const Ray ray{origin, square_to_uniform_sphere(rng.uniform2()), 0.0f, kInfinity};
      SurfaceHit a, b;
      const bool hit_a = direct->intersect(ray, a), hit_b = bvh->intersect(ray, b);
      ASSERT_EQ(hit_a, hit_b) << name << " ray " << i;
      if (!hit_a) continue;
      ++hits;
      EXPECT_NEAR(a.t, b.t, 1e-4f * std::max(1.0f, b.t)) << name << " ray " << i;
      // The same surface, except where the ray meets an edge (either triangle is right).
      if (a.geometry_id == b.geometry_id && a.primitive_id == b.primitive_id) {
        ++same_triangle;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR((&a.position.x)[k], (&b.position.x)[k], 1e-3f);
      }
      // A segment from the origin to just before the hit is free in both, and one past it
      // is blocked in both.
      const float t = std::min(a.t, b.t);
      const Ray before{origin, ray.direction, 0.0f, t * 0.999f};
      const Ray past{origin, ray.direction, 0.0f, t * 1.001f};
      EXPECT_FALSE(direct->occluded(before)) << name << " ray " << i;
      EXPECT_FALSE(bvh->occluded(before)) << name << " ray " << i;
      EXPECT_TRUE(direct->occluded(past)) << name << " ray " << i;
      EXPECT_TRUE(bvh->occluded(past)) << name << " ray " << i;
    }
    // Almost every ray from inside a closed box hits, and all but the edge cases name the
    // same triangle.
    EXPECT_GT(hits, 15000) << name;
    EXPECT_GT(same_triangle, hits - hits / 100) << name;
  }
}

TEST(DirectTriangles, SceneChoosesThemOnlyWhereTheyAnswerAsTheBvhWould) {
  SKIP_WITHOUT_DIRECT_TRIANGLES();
  const auto build = [](int rectangles, bool masked) {
    SceneDescription desc;
    desc.source = "direct-triangles-test";
    desc.materials.push_back({"grey", make_lambertian(Rgb(0.5f))});
    desc.camera.to_world = look_at_matrix(Vec3(0, 0, -20), Vec3(0, 0, 0), Vec3(0, 1, 0));
    desc.camera.width = desc.camera.height = 8;
    for (int i = 0; i < rectangles; ++i) {
      MeshDesc rect = make_rectangle_mesh(glm::translate(Mat4(1.0f), Vec3(0, 0, float(i))));
      rect.material = 0;
      if (i == 0) rect.emission = Rgb(1.0f);
      desc.meshes.push_back(rect);
    }
    if (masked) {
      desc.materials.push_back(
          MaterialDesc("masked", make_lambertian(Rgb(0.5f)), make_constant_texture(Rgb(0.5f))));
      desc.meshes.back().material = 1;
    }
    return Scene::build(std::move(desc));
  };
  EXPECT_TRUE(build(32, false)->stats().direct_triangles);   // 64 triangles
  EXPECT_FALSE(build(33, false)->stats().direct_triangles);  // 66: the BVH
  EXPECT_FALSE(build(2, true)->stats().direct_triangles);    // a mask needs Embree's filter
}
