#include "emlt/scene/shape_builders.h"

#include <utility>

namespace emlt {

namespace {

void add_quad(MeshDesc& mesh, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // a b c d counter-clockwise seen from the side the quad faces.
  const auto base = uint32_t(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {a, b, c, d});
  mesh.uvs.insert(mesh.uvs.end(), {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)});
  mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

}  // namespace

bool is_finite_matrix(const Mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

MeshDesc make_rectangle_mesh(const Mat4& to_world) {
  MeshDesc mesh;
  add_quad(mesh, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
  transform_mesh(mesh, to_world, true);
  return mesh;
}

MeshDesc make_cube_mesh(const Mat4& to_world) {
  MeshDesc mesh;
  // For each axis and sign, the face's two in-plane axes ordered so that
  // cross(first, second) = outward normal.
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {-1.0f, 1.0f}) {
      Vec3 n(0.0f), u(0.0f), v(0.0f);
      n[axis] = sign;
      u[(axis + 1) % 3] = 1.0f;
      v[(axis + 2) % 3] = 1.0f;
      if (sign < 0.0f) std::swap(u, v);
      add_quad(mesh, n - u - v, n + u - v, n + u + v, n - u + v);
    }
  }
  transform_mesh(mesh, to_world, true);
  return mesh;
}

MeshDesc make_disk_mesh(const Mat4& to_world, int segments) {
  MeshDesc mesh;
  const double polygon_area = 0.5 * segments * std::sin(2.0 * M_PI / segments);
  const auto rim = float(std::sqrt(M_PI / polygon_area));
  mesh.positions.push_back(Vec3(0.0f));
  mesh.uvs.push_back(Vec2(0.0f));
  for (int i = 0; i < segments; ++i) {
    const float phi = kTwoPi * float(i) / float(segments);
    mesh.positions.push_back(Vec3(rim * std::cos(phi), rim * std::sin(phi), 0.0f));
    mesh.uvs.push_back(Vec2(1.0f, float(i) / float(segments)));  // Mitsuba's (r, phi/2pi)
  }
  for (int i = 0; i < segments; ++i)
    mesh.indices.insert(mesh.indices.end(),
                        {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % segments)});
  transform_mesh(mesh, to_world, true);
  return mesh;
}

MeshDesc make_sphere_mesh(const Vec3& center, float radius, bool flip_normals, int segments,
                          int rings) {
  MeshDesc mesh;
  for (int ring = 0; ring <= rings; ++ring) {
    const float theta = kPi * float(ring) / float(rings);
    for (int seg = 0; seg <= segments; ++seg) {
      const float phi = kTwoPi * float(seg) / float(segments);
      const Vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                   std::cos(theta));
      mesh.positions.push_back(center + radius * n);
      mesh.normals.push_back(n);
      mesh.uvs.push_back(Vec2(float(seg) / float(segments), float(ring) / float(rings)));
    }
  }
  const auto row = uint32_t(segments + 1);
  for (uint32_t ring = 0; ring < uint32_t(rings); ++ring) {
    for (uint32_t seg = 0; seg < uint32_t(segments); ++seg) {
      const uint32_t a = ring * row + seg, b = a + 1, c = a + row, d = c + 1;
      // Outward winding; the pole rows produce one zero-area triangle each, skipped here.
      if (ring != 0) mesh.indices.insert(mesh.indices.end(), {a, c, b});
      if (ring + 1 != uint32_t(rings)) mesh.indices.insert(mesh.indices.end(), {b, c, d});
    }
  }
  if (flip_normals) flip_mesh_normals(mesh);
  return mesh;
}

void transform_mesh(MeshDesc& mesh, const Mat4& to_world, bool keep_facing) {
  const Mat3 normal_matrix = glm::transpose(glm::inverse(Mat3(to_world)));
  for (Vec3& p : mesh.positions) p = Vec3(to_world * Vec4(p, 1.0f));
  for (Vec3& n : mesh.normals) {
    const Vec3 m = normal_matrix * n;
    const float length = glm::length(m);
    n = length > 0.0f ? m / length : m;
  }
  if (keep_facing && glm::determinant(Mat3(to_world)) < 0.0f)
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
      std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
}

void flip_mesh_normals(MeshDesc& mesh) {
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
    std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
  for (Vec3& n : mesh.normals) n = -n;
}

}  // namespace emlt
