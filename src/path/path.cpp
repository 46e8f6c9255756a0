#include "emlt/path/path.h"

#include "emlt/path/connection.h"

namespace emlt {

PathType compute_path_type(std::span<const PathVertex> vertices) {
  PathType type;
  const size_t n = std::min(vertices.size(), size_t(PathType::kMaxVertices));
  type.vertices = uint8_t(n);
  for (size_t i = 1; i + 1 < n; ++i)
    if (vertices[i].delta) type.specular_mask |= uint64_t(1) << i;
  return type;
}

bool join_subpaths(const Scene& scene, std::span<const PathVertex> light, int s,
                   std::span<const PathVertex> camera, int t, Path& out) {
  const int n = s + t;
  if (s < 0 || t < 1 || n < 2 || n > kMaxPathVertices) return false;
  if (int(light.size()) < s || int(camera.size()) < t) return false;
  if (s == 0 && !camera[size_t(t - 1)].is_emitter()) return false;
  if (!camera[0].is_camera()) return false;

  VertexDensity densities[kMaxPathVertices];
  connection_densities(scene, light, s, camera, t, std::span(densities, size_t(n)));
  out.vertices.clear();
  out.vertices.reserve(size_t(n));
  for (int i = 0; i < s; ++i) out.vertices.push_back(light[size_t(i)]);
  for (int i = t - 1; i >= 0; --i) out.vertices.push_back(camera[size_t(i)]);
  for (int i = 0; i < n; ++i) {
    PathVertex& v = out.vertices[size_t(i)];
    v.pdf_from_light = densities[i].from_light;
    v.pdf_from_eye = densities[i].from_eye;
    v.delta = densities[i].delta;
  }
  out.type = compute_path_type(out.vertices);
  return true;
}

std::vector<VertexDensity> path_densities(const Path& path) {
  std::vector<VertexDensity> densities;
  densities.reserve(path.vertices.size());
  for (const PathVertex& v : path.vertices) densities.push_back(density_of(v));
  return densities;
}

double path_density(const Path& path, int s) {
  const auto densities = path_densities(path);
  return split_density(densities, s);
}

void recompute_densities(const Scene& scene, Path& path) {
  auto& x = path.vertices;
  const int k = int(x.size()) - 1;
  if (k < 1) return;
  for (int i = 0; i <= k; ++i) {
    PathVertex& v = x[size_t(i)];
    v.pdf_from_light = i == 0 ? pdf_light_origin(scene, v)
                              : pdf_towards(scene, i >= 2 ? &x[size_t(i - 2)] : nullptr,
                                            x[size_t(i - 1)], v);
    if (i == k) {
      float pdf_position = 0.0f, pdf_direction = 0.0f;
      scene.camera().pdf_emission(direction_between(v, x[size_t(k - 1)]), &pdf_position,
                                  &pdf_direction);
      v.pdf_from_eye = pdf_position;
    } else {
      v.pdf_from_eye = pdf_towards(scene, i + 2 <= k ? &x[size_t(i + 2)] : nullptr,
                                   x[size_t(i + 1)], v);
    }
  }
}

DVec3 path_contribution(const Scene& scene, const Path& path, InvalidCounter* invalid) {
  const auto& x = path.vertices;
  const int k = int(x.size()) - 1;
  if (k < 1) return DVec3(0.0);
  DVec3 f(1.0);
  for (int i = 0; i <= k && f != DVec3(0.0); ++i) {
    f *= DVec3(vertex_factor(scene, x[size_t(i)], i > 0 ? &x[size_t(i - 1)] : nullptr,
                             i < k ? &x[size_t(i + 1)] : nullptr));
    if (i < k) f *= double(geometry_term(x[size_t(i)], x[size_t(i + 1)]));
  }
  const bool valid = std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z) &&
                     f.x >= 0.0 && f.y >= 0.0 && f.z >= 0.0;
  if (!valid) {
    if (invalid) ++invalid->count;
    return DVec3(0.0);
  }
  return f;
}

double path_luminance(const Scene& scene, const Path& path) {
  const DVec3 f = path_contribution(scene, path);
  return 0.2126 * f.x + 0.7152 * f.y + 0.0722 * f.z;  // Rec. 709, as emlt::luminance
}

}  // namespace emlt
