#pragma once
// Small scenes built in code whose answers are known exactly.
#include <memory>

#include "emlt/scene/scene.h"

namespace emlt::test {

// Appends a quad (two triangles a b c, a c d) with normal along (b - a) x (c - a).
void add_quad(SceneDescription& d, Vec3 a, Vec3 b, Vec3 c, Vec3 e, int material,
              Rgb emission = Rgb(0.0f));
int add_material(SceneDescription& d, BsdfPtr bsdf);
CameraDesc camera_at(Vec3 eye, Vec3 target, int size, Vec3 up = Vec3(0, 1, 0));

// The inside of the cube [-1,1]^3, every face Lambertian with `albedo` and emitting `le`
// inwards. Radiance is the same everywhere: per channel, paths of k segments carry
// le * albedo^(k-1), so with at most K segments L = le * sum_{k<K} albedo^k.
std::unique_ptr<Scene> emissive_box(const Rgb& albedo, float le, int image_size = 16);
SceneDescription emissive_box_description(const Rgb& albedo, float le, int image_size = 16);
Rgb emissive_box_radiance(const Rgb& albedo, float le, int max_segments);

// The multi-chain perturbation's shortest path, L D S D E: a floor (faces +y), a
// downward-facing mirror at height 1 above its middle, a small light just above the floor
// further back, and a camera seeing the floor at a grazing angle. Returned as a description
// so that a test can add geometry (the geometry-aware test puts a sphere beside the path).
SceneDescription floor_mirror_description();

}  // namespace emlt::test
