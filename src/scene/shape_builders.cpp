#include "emlt/scene/shape_builders.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>

namespace emlt {

namespace {

void add_quad(MeshDesc& mesh, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
              bool clockwise = false) {
  // a b c d at uv (0,0) (1,0) (1,1) (0,1), counter-clockwise seen from the side the quad
  // faces (or clockwise, when `clockwise`: the quad then faces the other way).
  const auto base = uint32_t(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {a, b, c, d});
  mesh.uvs.insert(mesh.uvs.end(), {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)});
  if (clockwise)
    mesh.indices.insert(mesh.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
  else
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
  // Mitsuba 0.6's cube ([-1, 1]^3) parametrises each face with its own texture axes, which a
  // textured or anisotropic cube shows: per face, the corner at uv (0, 0) and the directions
  // of u and v (each spanning the face). E.g. on the top face u runs along -x and v along -z.
  struct Face {
    Vec3 outward, origin, u, v;
  };
  static const Face kFaces[] = {
      {{0, -1, 0}, {-1, -1, -1}, {0, 0, 2}, {2, 0, 0}},
      {{0, 1, 0}, {1, 1, 1}, {-2, 0, 0}, {0, 0, -2}},
      {{1, 0, 0}, {1, -1, 1}, {0, 2, 0}, {0, 0, -2}},
      {{0, 0, 1}, {-1, -1, 1}, {0, 2, 0}, {2, 0, 0}},
      {{-1, 0, 0}, {-1, -1, -1}, {0, 2, 0}, {0, 0, 2}},
      {{0, 0, -1}, {-1, 1, -1}, {0, -2, 0}, {2, 0, 0}},
  };
  MeshDesc mesh;
  for (const Face& f : kFaces)
    add_quad(mesh, f.origin, f.origin + f.u, f.origin + f.u + f.v, f.origin + f.v,
             glm::dot(glm::cross(f.u, f.v), f.outward) < 0.0f);
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

MeshDesc make_cylinder_mesh(const Vec3& p0, const Vec3& p1, float radius, const Mat4& to_world,
                            int segments) {
  // Mitsuba's object frame: translate(p0) * frame(axis) * scale(r, r, length), where the
  // frame's first two axes come from Mitsuba's coordinateSystem(); they fix where u = 0
  // lies on the rim, so they are reproduced rather than chosen freely.
  const Vec3 axis = p1 - p0;
  const Vec3 n = axis / glm::length(axis);
  const Vec3 t = std::abs(n.x) > std::abs(n.y)
                     ? Vec3(n.z, 0.0f, -n.x) / std::sqrt(n.x * n.x + n.z * n.z)
                     : Vec3(0.0f, n.z, -n.y) / std::sqrt(n.y * n.y + n.z * n.z);
  const Vec3 s = glm::cross(t, n);
  Mat4 object_to_world(1.0f);
  object_to_world[0] = Vec4(s * radius, 0.0f);
  object_to_world[1] = Vec4(t * radius, 0.0f);
  object_to_world[2] = Vec4(axis, 0.0f);
  object_to_world[3] = Vec4(p0, 1.0f);
  object_to_world = to_world * object_to_world;

  // Unit cylinder (radius 1, z in [0, 1]); the seam column is duplicated for u = 1.
  const double half_step = M_PI / segments;
  const auto rim = float(half_step / std::sin(half_step));  // perimeter = 2 pi exactly
  MeshDesc mesh;
  for (int i = 0; i <= segments; ++i) {
    const float phi = kTwoPi * float(i) / float(segments);
    const Vec3 outward(std::cos(phi), std::sin(phi), 0.0f);
    for (const float z : {0.0f, 1.0f}) {
      mesh.positions.push_back(Vec3(rim * outward.x, rim * outward.y, z));
      mesh.normals.push_back(outward);
      mesh.uvs.push_back(Vec2(float(i) / float(segments), z));
    }
  }
  for (uint32_t i = 0; i < uint32_t(segments); ++i) {
    const uint32_t a = 2 * i, b = a + 2, c = a + 3, d = a + 1;  // counter-clockwise outside
    mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
  }
  transform_mesh(mesh, object_to_world, false);
  // Mitsuba's normal is cross(dp/du, dp/dv) in world space, which a mirroring transform
  // turns inward, together with the winding (kept as transformed above).
  if (glm::determinant(Mat3(object_to_world)) < 0.0f)
    for (Vec3& normal : mesh.normals) normal = -normal;
  return mesh;
}

void compute_smooth_normals(MeshDesc& mesh) {
  mesh.normals.assign(mesh.positions.size(), Vec3(0.0f));
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const uint32_t corner[3] = {mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
    const Vec3 n = glm::cross(mesh.positions[corner[1]] - mesh.positions[corner[0]],
                              mesh.positions[corner[2]] - mesh.positions[corner[0]]);
    const float length = glm::length(n);
    if (!(length > 0.0f) || !std::isfinite(length)) continue;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = mesh.positions[corner[k]];
      const Vec3 e1 = glm::normalize(mesh.positions[corner[(k + 1) % 3]] - p);
      const Vec3 e2 = glm::normalize(mesh.positions[corner[(k + 2) % 3]] - p);
      mesh.normals[corner[k]] += safe_acos(glm::dot(e1, e2)) * (n / length);
    }
  }
  for (Vec3& n : mesh.normals) {
    const float length = glm::length(n);
    if (length > 0.0f) n /= length;
  }
}

void apply_mesh_normal_options(MeshDesc& mesh, bool face_normals, bool flip_normals) {
  if (face_normals) {
    mesh.normals.clear();
    if (flip_normals)
      for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
        std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
    return;
  }
  if (mesh.normals.empty()) compute_smooth_normals(mesh);
  // The vertex normals orient the surface, so the winding stays as it is.
  if (flip_normals)
    for (Vec3& n : mesh.normals) n = -n;
}

void split_vertices_by_angle(MeshDesc& mesh, float max_angle_degrees) {
  const float cos_limit = std::cos(glm::radians(max_angle_degrees));
  const size_t corners = mesh.indices.size() - mesh.indices.size() % 3;
  const bool has_uvs = mesh.uvs.size() == mesh.positions.size();
  const bool has_colors = mesh.colors.size() == mesh.positions.size();
  std::vector<Vec3> face_normals(corners / 3, Vec3(0.0f));
  for (size_t f = 0; f < corners / 3; ++f) {
    const Vec3& a = mesh.positions[mesh.indices[3 * f]];
    const Vec3 n = glm::cross(mesh.positions[mesh.indices[3 * f + 1]] - a,
                              mesh.positions[mesh.indices[3 * f + 2]] - a);
    const float length = glm::length(n);
    if (length > 1e-30f) face_normals[f] = n / length;  // degenerate faces keep 0
  }
  // Corners are grouped by their vertex's position, uv and colour (Mitsuba keeps vertices
  // of different colours apart) compared bit for bit (a strict order even for NaN; -0
  // counts as +0, as a float comparison would have it).
  using Key = std::array<uint32_t, 8>;
  auto bits = [](float x) { return std::bit_cast<uint32_t>(x == 0.0f ? 0.0f : x); };
  std::vector<Key> keys(corners);
  for (size_t c = 0; c < corners; ++c) {
    const uint32_t v = mesh.indices[c];
    const Vec3& p = mesh.positions[v];
    const Vec2 uv = has_uvs ? mesh.uvs[v] : Vec2(0.0f);
    const Rgb color = has_colors ? mesh.colors[v] : Rgb(0.0f);
    keys[c] = {bits(p.x),  bits(p.y),     bits(p.z),     bits(uv.x),
               bits(uv.y), bits(color.x), bits(color.y), bits(color.z)};
  }
  std::vector<uint32_t> order(corners);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });

  // Greedy clustering within each group, in corner order: a new vertex takes every
  // remaining corner whose face normal is close to the first remaining one's.
  std::vector<Vec3> positions;
  std::vector<Vec2> uvs;
  std::vector<Rgb> colors;
  std::vector<uint32_t> indices(corners);
  std::vector<char> clustered(corners, 0);
  for (size_t begin = 0; begin < corners;) {
    size_t end = begin + 1;
    while (end < corners && keys[order[end]] == keys[order[begin]]) ++end;
    for (size_t a = begin; a < end; ++a) {
      if (clustered[a]) continue;
      const Vec3 n1 = face_normals[order[a] / 3];
      const auto vertex = uint32_t(positions.size());
      positions.push_back(mesh.positions[mesh.indices[order[a]]]);
      if (has_uvs) uvs.push_back(mesh.uvs[mesh.indices[order[a]]]);
      if (has_colors) colors.push_back(mesh.colors[mesh.indices[order[a]]]);
      for (size_t b = a; b < end; ++b) {
        const Vec3 n2 = face_normals[order[b] / 3];
        if (!clustered[b] && (n1 == n2 || glm::dot(n1, n2) > cos_limit)) {
          indices[order[b]] = vertex;
          clustered[b] = 1;
        }
      }
    }
    begin = end;
  }
  mesh.positions = std::move(positions);
  mesh.uvs = std::move(uvs);
  mesh.colors = std::move(colors);
  mesh.indices = std::move(indices);
  mesh.normals.clear();
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
