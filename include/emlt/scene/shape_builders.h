#pragma once
// Mitsuba 0.6's canonical shapes as triangle meshes, and mesh transforms shared by the
// loaders. Canonical frames (before `to_world`):
//   rectangle  [-1,1]^2 in the z = 0 plane, normal +z
//   cube       [-1,1]^3, outward normals
//   disk       unit disk in the z = 0 plane, normal +z
// Spheres stay analytic in the scene (SphereDesc); make_sphere_mesh only serves emissive
// spheres, which become triangle lights.
#include <string>

#include "emlt/scene/description.h"

namespace emlt {

MeshDesc make_rectangle_mesh(const Mat4& to_world);
MeshDesc make_cube_mesh(const Mat4& to_world);
// The rim is pushed out slightly so the polygon's area equals the disk's (pi), which keeps
// an emissive disk's power exact.
MeshDesc make_disk_mesh(const Mat4& to_world, int segments = 64);
// UV sphere with smooth (outward, or inward when flipped) vertex normals.
MeshDesc make_sphere_mesh(const Vec3& center, float radius, bool flip_normals, int segments = 64,
                          int rings = 32);

// Positions by the matrix, normals by its inverse transpose. A mirroring matrix reverses
// the winding (and with it the triangle normal); `keep_facing` re-reverses it so the
// facing follows the transformed normal, as Mitsuba's analytic shapes do.
void transform_mesh(MeshDesc& mesh, const Mat4& to_world, bool keep_facing);
// Reverses the winding and negates vertex normals (Mitsuba's flipNormals).
void flip_mesh_normals(MeshDesc& mesh);

bool is_finite_matrix(const Mat4& m);

}  // namespace emlt
