// Scene::build and ray queries on small hand-built descriptions with known answers.
#include "emlt/scene/scene.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>

#include "emlt/core/error.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/shape_builders.h"

using namespace emlt;

namespace {

constexpr float kTolerance = 1e-4f;

// A unit-ish test scene: a grey material and an emissive rectangle far away so every
// description has an emitter.
SceneDescription base_description() {
  SceneDescription desc;
  desc.source = "test-scene";
  desc.materials.push_back({"grey", make_lambertian(Rgb(0.5f))});
  desc.camera.to_world = look_at_matrix(Vec3(0, 0, -20), Vec3(0, 0, 0), Vec3(0, 1, 0));
  desc.camera.width = desc.camera.height = 32;
  MeshDesc light = make_rectangle_mesh(glm::translate(Mat4(1.0f), Vec3(0, 100, 0)) *
                                       glm::rotate(Mat4(1.0f), glm::radians(90.0f), Vec3(1, 0, 0)));
  light.name = "light";
  light.material = 0;
  light.emission = Rgb(1.0f);
  desc.meshes.push_back(light);
  return desc;
}

Ray ray_towards(const Vec3& origin, const Vec3& target) {
  return Ray{origin, glm::normalize(target - origin), 0.0f, kInfinity};
}

void expect_near(const Vec3& a, const Vec3& b, float tolerance = kTolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

std::string build_error(SceneDescription desc) {
  try {
    Scene::build(std::move(desc));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(LookAt, FollowsMitsubaConvention) {
  const Mat4 m = look_at_matrix(Vec3(1, 2, 3), Vec3(1, 2, 10), Vec3(0, 1, 0));
  expect_near(Vec3(m[2]), Vec3(0, 0, 1));  // forward
  expect_near(Vec3(m[0]), Vec3(1, 0, 0));  // left = cross(up, dir)
  expect_near(Vec3(m[1]), Vec3(0, 1, 0));
  expect_near(Vec3(m[3]), Vec3(1, 2, 3));
}

TEST(ShapeBuilders, CanonicalShapesHaveExpectedAreaAndFacing) {
  auto area_and_normal = [](const MeshDesc& mesh) {
    float area = 0.0f;
    Vec3 weighted(0.0f);
    for (size_t i = 0; i < mesh.indices.size(); i += 3) {
      const Vec3 c =
          glm::cross(mesh.positions[mesh.indices[i + 1]] - mesh.positions[mesh.indices[i]],
                     mesh.positions[mesh.indices[i + 2]] - mesh.positions[mesh.indices[i]]);
      area += 0.5f * glm::length(c);
      weighted += 0.5f * c;
    }
    return std::make_pair(area, weighted);
  };
  auto [rect_area, rect_n] = area_and_normal(make_rectangle_mesh(Mat4(1.0f)));
  EXPECT_NEAR(rect_area, 4.0f, 1e-5f);
  expect_near(rect_n / rect_area, Vec3(0, 0, 1));
  auto [disk_area, disk_n] = area_and_normal(make_disk_mesh(Mat4(1.0f)));
  EXPECT_NEAR(disk_area, kPi, 1e-4f);
  expect_near(disk_n / disk_area, Vec3(0, 0, 1));

  const MeshDesc cube = make_cube_mesh(Mat4(1.0f));
  EXPECT_EQ(cube.indices.size(), 36u);
  for (size_t i = 0; i < cube.indices.size(); i += 3) {
    const Vec3 a = cube.positions[cube.indices[i]], b = cube.positions[cube.indices[i + 1]],
               c = cube.positions[cube.indices[i + 2]];
    const Vec3 n = glm::cross(b - a, c - a);
    EXPECT_GT(glm::dot(n, (a + b + c) / 3.0f), 0.0f)
        << "cube triangle " << i / 3 << " faces inward";
  }
  // Mitsuba 0.6's cube parametrisation (its cube.cpp table): on the top face u = (1 - x) / 2
  // and v = (1 - z) / 2, on the front (+z) face u = (1 + y) / 2 and v = (1 + x) / 2, on the
  // bottom face u = (1 + z) / 2 and v = (1 + x) / 2: each vertex's uv against those.
  const auto expected_uv = [](const Vec3& p) {
    if (p.y > 0.999f && std::abs(p.x) <= 1 && std::abs(p.z) <= 1)
      return std::optional<Vec2>(Vec2((1 - p.x) / 2, (1 - p.z) / 2));
    return std::optional<Vec2>();
  };
  int top_vertices = 0;
  for (size_t i = 0; i < cube.indices.size(); i += 3) {
    const Vec3 a = cube.positions[cube.indices[i]], b = cube.positions[cube.indices[i + 1]],
               c = cube.positions[cube.indices[i + 2]];
    const Vec3 n = glm::normalize(glm::cross(b - a, c - a));
    for (int k = 0; k < 3; ++k) {
      const uint32_t index = cube.indices[i + size_t(k)];
      const Vec3 p = cube.positions[index];
      const Vec2 uv = cube.uvs[index];
      std::optional<Vec2> want;
      if (n.y > 0.5f) want = expected_uv(p), ++top_vertices;
      if (n.z > 0.5f) want = Vec2((1 + p.y) / 2, (1 + p.x) / 2);
      if (n.y < -0.5f) want = Vec2((1 + p.z) / 2, (1 + p.x) / 2);
      if (want) {
        EXPECT_NEAR(uv.x, want->x, 1e-6f) << "triangle " << i / 3 << " vertex " << k;
        EXPECT_NEAR(uv.y, want->y, 1e-6f) << "triangle " << i / 3 << " vertex " << k;
      }
    }
  }
  EXPECT_EQ(top_vertices, 6);
  // A mirroring transform keeps the rectangle facing along the transformed normal (+z).
  auto [mirrored_area, mirrored_n] =
      area_and_normal(make_rectangle_mesh(glm::scale(Mat4(1.0f), Vec3(-1, 1, 1))));
  expect_near(mirrored_n / mirrored_area, Vec3(0, 0, 1));
}

TEST(Scene, RectangleHitHasExactDistanceNormalAndUv) {
  SceneDescription desc = base_description();
  MeshDesc rect = make_rectangle_mesh(glm::scale(Mat4(1.0f), Vec3(2.0f)));
  rect.material = 0;
  desc.meshes.push_back(rect);
  const auto scene = Scene::build(desc);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.5f, -1.0f, 5.0f), Vec3(0, 0, -1)}, hit));
  EXPECT_NEAR(hit.t, 5.0f, kTolerance);
  expect_near(hit.position, Vec3(0.5f, -1.0f, 0.0f));
  expect_near(hit.geometric_normal, Vec3(0, 0, 1));
  expect_near(hit.shading_normal, Vec3(0, 0, 1));
  expect_near(hit.shading.n, Vec3(0, 0, 1));
  EXPECT_NEAR(hit.uv.x, (0.5f / 2.0f + 1.0f) / 2.0f, kTolerance);
  EXPECT_NEAR(hit.uv.y, (-1.0f / 2.0f + 1.0f) / 2.0f, kTolerance);
  EXPECT_EQ(hit.bsdf, desc.materials[0].bsdf.get());
  EXPECT_EQ(hit.light, nullptr);
  EXPECT_FALSE(scene->intersect(Ray{Vec3(5.0f, 0.0f, 5.0f), Vec3(0, 0, -1)}, hit));
  // tmax before the surface: no hit.
  EXPECT_FALSE(scene->intersect(Ray{Vec3(0.0f, 0.0f, 5.0f), Vec3(0, 0, -1), 0.0f, 4.9f}, hit));
}

TEST(Scene, CubeHitIsOnTheNearFaceWithOutwardNormal) {
  SceneDescription desc = base_description();
  MeshDesc cube = make_cube_mesh(glm::translate(Mat4(1.0f), Vec3(0, 0, 3)));
  cube.material = 0;
  desc.meshes.push_back(cube);
  const auto scene = Scene::build(desc);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(ray_towards(Vec3(0.3f, 0.2f, -10), Vec3(0.3f, 0.2f, 0)), hit));
  EXPECT_NEAR(hit.t, 12.0f, kTolerance);
  expect_near(hit.geometric_normal, Vec3(0, 0, -1));
  ASSERT_TRUE(scene->intersect(ray_towards(Vec3(10, 0.1f, 3.2f), Vec3(0, 0.1f, 3.2f)), hit));
  EXPECT_NEAR(hit.t, 9.0f, kTolerance);
  expect_near(hit.geometric_normal, Vec3(1, 0, 0));
}

TEST(Scene, SphereReportsEntryAndExitHits) {
  SceneDescription desc = base_description();
  desc.spheres.push_back({"ball", Vec3(1, 2, 3), 2.0f, 0, Rgb(0.0f), false});
  const auto scene = Scene::build(desc);
  EXPECT_EQ(scene->stats().spheres, 1u);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(1, 2, -7), Vec3(0, 0, 1)}, hit));
  EXPECT_NEAR(hit.t, 8.0f, kTolerance);
  expect_near(hit.position, Vec3(1, 2, 1));
  expect_near(hit.geometric_normal, Vec3(0, 0, -1));

  // From inside (what refraction into glass produces) the exit point must be found.
  for (const Vec3& dir : {Vec3(0, 0, 1), glm::normalize(Vec3(1, 1, 0)), Vec3(0, -1, 0)}) {
    ASSERT_TRUE(scene->intersect(Ray{Vec3(1, 2, 3), dir}, hit))
        << "direction " << dir.x << dir.y << dir.z;
    EXPECT_NEAR(hit.t, 2.0f, kTolerance);
    expect_near(hit.geometric_normal, dir);  // outward, i.e. along the ray when leaving
  }
  // A ray spawned just inside the entry point (glass refraction) exits on the far side.
  ASSERT_TRUE(scene->intersect(Ray{Vec3(1, 2, -7), Vec3(0, 0, 1)}, hit));
  const Ray inside = spawn_ray(hit.position, hit.geometric_normal, Vec3(0, 0, 1));
  ASSERT_TRUE(scene->intersect(inside, hit));
  expect_near(hit.position, Vec3(1, 2, 5), 1e-3f);

  // flip_normals turns the normal inwards.
  SceneDescription flipped = base_description();
  flipped.spheres.push_back({"ball", Vec3(0), 1.0f, 0, Rgb(0.0f), true});
  const auto flipped_scene = Scene::build(flipped);
  ASSERT_TRUE(flipped_scene->intersect(Ray{Vec3(0, 0, -5), Vec3(0, 0, 1)}, hit));
  expect_near(hit.geometric_normal, Vec3(0, 0, 1));
}

TEST(Scene, SpawnedRaysDoNotSelfIntersectALargeSphere) {
  // The Cornell-glass sphere: radius 100 seen from ~1000 away, where float error in the
  // quadratic is largest relative to the ray offset.
  SceneDescription desc = base_description();
  const Vec3 center(185, 100, 170);
  const float radius = 100.0f;
  desc.spheres.push_back({"glass", center, radius, 0, Rgb(0.0f), false});
  const auto scene = Scene::build(desc);
  const Vec3 eye(278, 273, -800);
  int failures = 0;
  for (int i = 0; i < 400; ++i) {
    // Deterministic target points spread over the visible cap.
    const float a = 0.37f * float(i), b = 0.61f * float(i);
    const Vec3 target = center + 0.95f * radius *
                                     Vec3(std::sin(a) * std::cos(b), std::cos(a),
                                          -std::abs(std::sin(a) * std::sin(b)));
    SurfaceHit entry;
    if (!scene->intersect(ray_towards(eye, target), entry)) continue;
    const Vec3 d = glm::normalize(target - eye);
    // Straight through: the next hit is the exit point, a full chord away.
    SurfaceHit exit;
    const bool found_exit =
        scene->intersect(spawn_ray(entry.position, entry.geometric_normal, d), exit);
    const float chord = -2.0f * glm::dot(d, entry.geometric_normal) * radius;
    failures += !found_exit || std::abs(exit.t - chord) > 1e-2f * radius;
    // Mirror reflection leaves the sphere for good.
    const Vec3 reflected = reflect_about(-d, entry.geometric_normal);
    SurfaceHit again;
    failures +=
        scene->intersect(spawn_ray(entry.position, entry.geometric_normal, reflected), again) &&
        again.geometry_id == entry.geometry_id;
  }
  EXPECT_EQ(failures, 0);
}

TEST(Scene, OccludedAndVisibleRespectBlockers) {
  SceneDescription desc = base_description();
  MeshDesc wall = make_rectangle_mesh(Mat4(1.0f));  // [-1,1]^2 at z = 0
  wall.material = 0;
  desc.meshes.push_back(wall);
  MeshDesc floor = make_rectangle_mesh(glm::translate(Mat4(1.0f), Vec3(0, 0, 5)) *
                                       glm::scale(Mat4(1.0f), Vec3(10.0f)));
  floor.material = 0;
  desc.meshes.push_back(floor);
  const auto scene = Scene::build(desc);
  EXPECT_TRUE(scene->occluded(Ray{Vec3(0, 0, -3), Vec3(0, 0, 1), 0.0f, 10.0f}));
  EXPECT_FALSE(scene->occluded(Ray{Vec3(0, 0, -3), Vec3(0, 0, 1), 0.0f, 2.9f}));
  EXPECT_FALSE(scene->occluded(Ray{Vec3(3, 0, -3), Vec3(0, 0, 1), 0.0f, 7.9f}));
  // Points on the z = 5 plate see each other along it, and see (0,0,-3) only when the
  // segment passes beside the wall.
  const Vec3 n(0, 0, -1);
  EXPECT_TRUE(scene->visible(Vec3(3, 0, 5), n, Vec3(-3, 0, 5), n));  // along the surface itself
  EXPECT_TRUE(scene->visible(Vec3(0, 0, -3), Vec3(0, 0, -1), Vec3(3, 0, 5), n));
  EXPECT_FALSE(scene->visible(Vec3(0, 0, -3), Vec3(0, 0, 1), Vec3(0, 0, 5), n));
  // A point on the wall sees a point on the floor behind it.
  EXPECT_TRUE(scene->visible(Vec3(0.5f, 0.5f, 0), Vec3(0, 0, 1), Vec3(0.5f, 0.5f, 5), n));
}

TEST(Scene, TrianglesAfterADroppedOneKeepTheirCorners) {
  // The kept triangles are compacted over the mesh's own indices: each must keep its own
  // corners and winding wherever it lands.
  SceneDescription desc = base_description();
  MeshDesc mesh;
  mesh.name = "two triangles and two degenerate ones";
  mesh.material = 0;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 0, 0}, {6, 0, 0},
                    {5, 1, 0}, {0, 3, 0}, {1, 3, 0}, {0, 4, 0}};
  mesh.indices = {0, 1, 2,   // collinear: dropped
                  3, 4, 5,   // kept, normal +z
                  3, 3, 4,   // repeated vertex: dropped
                  8, 7, 6};  // kept, normal -z
  desc.meshes.push_back(mesh);
  const auto scene = Scene::build(std::move(desc));
  EXPECT_EQ(scene->stats().dropped_degenerate_triangles, 2u);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(ray_towards(Vec3(5.2f, 0.2f, 3), Vec3(5.2f, 0.2f, 0)), hit));
  expect_near(hit.position, Vec3(5.2f, 0.2f, 0));
  expect_near(hit.geometric_normal, Vec3(0, 0, 1));
  ASSERT_TRUE(scene->intersect(ray_towards(Vec3(0.2f, 3.2f, 3), Vec3(0.2f, 3.2f, 0)), hit));
  expect_near(hit.position, Vec3(0.2f, 3.2f, 0));
  expect_near(hit.geometric_normal, Vec3(0, 0, -1));
}

TEST(Scene, DegenerateTrianglesAreDroppedAndCounted) {
  SceneDescription desc = base_description();
  MeshDesc mesh;
  mesh.name = "messy";
  mesh.material = 0;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {nan, 0, 0}, {0, kInfinity, 0}};
  mesh.indices = {0, 1, 2,   // fine
                  0, 1, 3,   // collinear: zero area
                  0, 0, 2,   // repeated vertex
                  0, 1, 4,   // NaN
                  0, 5, 1,   // infinity
                  2, 1, 0};  // fine (other side)
  desc.meshes.push_back(mesh);
  const auto scene = Scene::build(desc);
  EXPECT_EQ(scene->stats().dropped_degenerate_triangles, 4u);
  EXPECT_EQ(scene->stats().triangles, 2u + 2u);  // + the light's two
  bool warned = false;
  for (const std::string& w : scene->warnings())
    warned |= w.find("4 degenerate triangles dropped") != std::string::npos;
  EXPECT_TRUE(warned);

  SceneDescription bad = base_description();
  mesh.indices = {0, 1, 2, 0, 1, 17};
  bad.meshes.push_back(mesh);
  const std::string message = build_error(bad);
  EXPECT_NE(message.find("messy"), std::string::npos) << message;
  EXPECT_NE(message.find("out of range"), std::string::npos) << message;
}

TEST(Scene, EmissionIsOneSidedAndLinkedToTheLight) {
  SceneDescription desc = base_description();
  MeshDesc panel = make_rectangle_mesh(Mat4(1.0f));
  panel.name = "panel";
  panel.material = 0;
  panel.emission = Rgb(2.0f, 3.0f, 4.0f);
  desc.meshes.push_back(panel);
  const auto scene = Scene::build(desc);
  EXPECT_EQ(scene->stats().area_lights, 4u);  // 2 panel + 2 base light triangles
  EXPECT_EQ(scene->lights().size(), 4u);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.1f, 0.1f, 3), Vec3(0, 0, -1)}, hit));
  ASSERT_NE(hit.light, nullptr);
  expect_near(hit.emitted(Vec3(0, 0, 1)), Rgb(2, 3, 4));
  EXPECT_TRUE(is_black(hit.emitted(Vec3(0, 0, -1))));
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.1f, 0.1f, -3), Vec3(0, 0, 1)}, hit));
  EXPECT_TRUE(is_black(hit.emitted(Vec3(0, 0, -1))));  // back side is dark
}

TEST(Scene, EmissiveSphereBecomesTriangleLights) {
  SceneDescription desc = base_description();
  desc.meshes.clear();  // the sphere is the only emitter
  desc.spheres.push_back({"bulb", Vec3(0), 1.0f, 0, Rgb(1.0f), false});
  const auto scene = Scene::build(desc);
  EXPECT_EQ(scene->stats().spheres, 0u);
  EXPECT_GT(scene->stats().area_lights, 1000u);
  // Power of a unit sphere of radiance 1: pi * area = 4 pi^2 (tessellation a bit smaller).
  double power = 0.0;
  for (size_t i = 0; i < scene->lights().size(); ++i) power += scene->lights().light(i).power().x;
  EXPECT_NEAR(power, 4.0 * kPi * kPi, 0.01 * 4.0 * kPi * kPi);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.2f, 0.1f, -5), Vec3(0, 0, 1)}, hit));
  EXPECT_NE(hit.light, nullptr);
  EXPECT_LT(glm::dot(hit.shading_normal, Vec3(0, 0, 1)), 0.0f);  // smooth, outward
}

TEST(Scene, VertexNormalsOrientTheSurfaceAsInMitsuba) {
  SceneDescription desc = base_description();
  MeshDesc mesh;
  mesh.name = "tilted";
  mesh.material = 0;
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};                               // winding normal +z
  const Vec3 tilted = glm::normalize(Vec3(0.3f, 0, -1));  // opposite side of the winding
  mesh.normals = {tilted, tilted, tilted};
  desc.meshes.push_back(mesh);
  const auto scene = Scene::build(desc);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0, 0, 2), Vec3(0, 0, -1)}, hit));
  // Mitsuba (and pbrt) turn the geometric normal to the vertex normals' side, not the
  // other way round: this surface's outside faces -z.
  expect_near(hit.geometric_normal, Vec3(0, 0, -1));
  expect_near(hit.shading_normal, tilted);
  expect_near(hit.shading.n, tilted);
  // No uvs given: barycentrics.
  EXPECT_GE(hit.uv.x, 0.0f);
  EXPECT_LE(hit.uv.x + hit.uv.y, 1.0f);
}

TEST(Scene, EmitterWithVertexNormalsEmitsOnTheirSide) {
  // The lamp of Veach's door scene as published for Mitsuba: one quad wound to face up
  // whose vertex normals face down. Mitsuba lights the room below with it.
  SceneDescription desc = base_description();
  desc.meshes.clear();
  MeshDesc lamp;
  lamp.name = "lamp";
  lamp.material = 0;
  lamp.positions = {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}};
  lamp.indices = {0, 1, 2, 0, 2, 3};  // (p1 - p0) x (p2 - p0) = +y
  lamp.normals.assign(4, Vec3(0, -1, 0));
  lamp.emission = Rgb(5.0f);
  desc.meshes.push_back(lamp);
  const auto scene = Scene::build(desc);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.2f, -3, 0.1f), Vec3(0, 1, 0)}, hit));
  expect_near(hit.emitted(Vec3(0, -1, 0)), Rgb(5.0f));
  // Light sampling agrees: a point below sees the lamp, a point above does not.
  ASSERT_EQ(scene->lights().size(), 2u);
  const auto below = scene->lights().light(0).sample_direct(Vec3(0, -2, 0), Vec2(0.3f, 0.4f));
  ASSERT_TRUE(below.has_value());
  EXPECT_GT(below->radiance.x, 0.0f);
  EXPECT_FALSE(scene->lights().light(0).sample_direct(Vec3(0, 2, 0), Vec2(0.3f, 0.4f)).has_value());
}

TEST(Scene, MissingMaterialGetsDefaultWithWarning) {
  SceneDescription desc = base_description();
  MeshDesc rect = make_rectangle_mesh(Mat4(1.0f));
  rect.name = "bare";
  desc.meshes.push_back(rect);
  const auto scene = Scene::build(desc);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0, 0, 2), Vec3(0, 0, -1)}, hit));
  ASSERT_NE(hit.bsdf, nullptr);
  const Rgb f = hit.bsdf->eval({}, Vec3(0, 0, 1), glm::normalize(Vec3(0.2f, 0.1f, 1)));
  EXPECT_NEAR(f.x, 0.5f * kInvPi, 1e-5f);
  bool warned = false;
  for (const std::string& w : scene->warnings()) warned |= w.find("bare") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(Scene, BuildRejectsUnusableDescriptions) {
  SceneDescription no_emitter = base_description();
  no_emitter.meshes[0].emission = Rgb(0.0f);
  EXPECT_NE(build_error(no_emitter).find("test-scene: scene has no emitter"), std::string::npos);

  SceneDescription no_geometry = base_description();
  no_geometry.meshes.clear();
  no_geometry.environment.kind = EnvironmentDesc::Kind::Constant;
  no_geometry.environment.radiance = Rgb(1.0f);
  EXPECT_NE(build_error(no_geometry).find("no geometry"), std::string::npos);

  for (auto [w, h] : {std::pair{0, 32}, {32, -1}, {100000, 100000}, {16385, 1}, {16384, 16385}}) {
    SceneDescription bad = base_description();
    bad.camera.width = w;
    bad.camera.height = h;
    EXPECT_NE(build_error(bad).find("resolution"), std::string::npos) << w << "x" << h;
  }
  SceneDescription nan_camera = base_description();
  nan_camera.camera.to_world[3][1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(build_error(nan_camera).find("NaN"), std::string::npos);

  SceneDescription bad_material = base_description();
  bad_material.meshes[0].material = 5;
  EXPECT_NE(build_error(bad_material).find("material"), std::string::npos);
}

TEST(Scene, ConstantEnvironmentAloneIsAnEmitter) {
  SceneDescription desc = base_description();
  desc.meshes[0].emission = Rgb(0.0f);
  desc.environment.kind = EnvironmentDesc::Kind::Constant;
  desc.environment.radiance = Rgb(0.5f);
  const auto scene = Scene::build(desc);
  ASSERT_NE(scene->environment(), nullptr);
  EXPECT_TRUE(scene->stats().has_environment);
  EXPECT_EQ(scene->lights().size(), 1u);
  EXPECT_GT(scene->bounds_radius(), 1.0f);
}

TEST(Scene, ConcurrentQueriesAgreeWithSerialOnes) {
  SceneDescription desc = base_description();
  desc.spheres.push_back({"ball", Vec3(0), 1.0f, 0, Rgb(0.0f), false});
  MeshDesc cube = make_cube_mesh(glm::translate(Mat4(1.0f), Vec3(3, 0, 0)));
  cube.material = 0;
  desc.meshes.push_back(cube);
  const auto scene = Scene::build(desc);
  const int n = 20000;
  auto ray_for = [](int i) {
    const float a = float(i) * 0.001f;
    return ray_towards(Vec3(1.5f, 0, -10),
                       Vec3(1.5f + 3.0f * std::cos(a), 1.5f * std::sin(3 * a), 0));
  };
  std::vector<float> serial(n);
  for (int i = 0; i < n; ++i) {
    SurfaceHit hit;
    serial[size_t(i)] = scene->intersect(ray_for(i), hit) ? hit.t : -1.0f;
  }
  std::atomic<int> mismatches{0};
  tbb::parallel_for(0, n, [&](int i) {
    SurfaceHit hit;
    const float t = scene->intersect(ray_for(i), hit) ? hit.t : -1.0f;
    if (t != serial[size_t(i)]) ++mismatches;
  });
  EXPECT_EQ(mismatches.load(), 0);
}
