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
// Mitsuba's cylinder (no caps): radius `radius` around the segment p0 -> p1, then
// `to_world`, with smooth vertex normals pointing outward and Mitsuba's uv
// (u = angle / 2pi about the axis, v = 0 at p0 and 1 at p1). As for the disk, the rim is
// pushed out so the prism's area equals the cylinder's. Callers check radius > 0 and
// p0 != p1.
MeshDesc make_cylinder_mesh(const Vec3& p0, const Vec3& p1, float radius, const Mat4& to_world,
                            int segments = 64);

// Angle-weighted vertex normals from the winding (Thuermer and Wuethrich 1998): unlike
// area weighting, the result does not depend on how polygons were split into triangles.
void compute_smooth_normals(MeshDesc& mesh);
// Mitsuba's TriMesh normal rules for meshes read from files (serialized, ply):
// faceNormals drops the vertex normals (flipNormals then reverses the winding);
// otherwise missing normals are computed smooth and flipNormals negates them.
void apply_mesh_normal_options(MeshDesc& mesh, bool face_normals, bool flip_normals);
// Mitsuba's maxSmoothAngle: corners sharing a position and uv are merged into one vertex
// as long as their faces' normals lie within `max_angle_degrees` of the first face of the
// cluster; vertex normals are dropped (apply_mesh_normal_options recomputes them).
void split_vertices_by_angle(MeshDesc& mesh, float max_angle_degrees);

// Positions by the matrix, normals by its inverse transpose. A mirroring matrix reverses
// the winding (and with it the triangle normal); `keep_facing` re-reverses it so the
// facing follows the transformed normal, as Mitsuba's analytic shapes do.
void transform_mesh(MeshDesc& mesh, const Mat4& to_world, bool keep_facing);
// Reverses the winding and negates vertex normals (Mitsuba's flipNormals).
void flip_mesh_normals(MeshDesc& mesh);

bool is_finite_matrix(const Mat4& m);

}  // namespace emlt
