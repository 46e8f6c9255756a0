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
  recompute_densities(scene, path, 0, int(path.vertices.size()) - 1);
}

void recompute_densities(const Scene& scene, Path& path, int first, int last) {
  auto& x = path.vertices;
  const int k = int(x.size()) - 1;
  if (k < 1) return;
  first = std::max(first, 0);
  last = std::min(last, k);
  if (first > last) return;
  // Every segment the recomputed densities use, once: segment[i] runs from x_i to x_{i+1}.
  const int lo = std::max(first - 2, 0), hi = std::min(last + 2, k);
  Segment local[kMaxPathVertices];
  std::vector<Segment> heap;
  Segment* segment = local;
  if (k > kMaxPathVertices) {
    heap.resize(size_t(k));
    segment = heap.data();
  }
  for (int i = lo; i < hi; ++i) segment[i] = segment_between(x[size_t(i)], x[size_t(i + 1)]);
  const auto reversed = [&](int i) { return Segment{-segment[i].w, segment[i].distance_squared}; };

  // pdf_from_light of x_i depends on x_{i-2}, x_{i-1}, x_i.
  for (int i = first; i <= hi; ++i) {
    PathVertex& v = x[size_t(i)];
    if (i == 0) {
      v.pdf_from_light = pdf_light_origin(scene, v);
    } else if (i == 1) {
      v.pdf_from_light = pdf_towards_along(scene, nullptr, x[0], v, segment[0], nullptr);
    } else {
      const Vec3 back = -segment[i - 2].w;
      v.pdf_from_light = pdf_towards_along(scene, &x[size_t(i - 2)], x[size_t(i - 1)], v,
                                           segment[i - 1], &back);
    }
  }
  // pdf_from_eye of x_i depends on x_i, x_{i+1}, x_{i+2}.
  for (int i = lo; i <= last; ++i) {
    PathVertex& v = x[size_t(i)];
    if (i == k) {
      float pdf_position = 0.0f, pdf_direction = 0.0f;
      scene.camera().pdf_emission(reversed(k - 1).w, &pdf_position, &pdf_direction);
      v.pdf_from_eye = pdf_position;
    } else if (i == k - 1) {
      v.pdf_from_eye = pdf_towards_along(scene, nullptr, x[size_t(k)], v, reversed(k - 1), nullptr);
    } else {
      v.pdf_from_eye = pdf_towards_along(scene, &x[size_t(i + 2)], x[size_t(i + 1)], v, reversed(i),
                                         &segment[i + 1].w);
    }
  }
}

DVec3 path_contribution(const Scene& scene, const Path& path, InvalidCounter* invalid) {
  const auto& x = path.vertices;
  const int k = int(x.size()) - 1;
  if (k < 1) return DVec3(0.0);
  DVec3 f(1.0);
  // Each segment is computed once and read from both of its ends (its reverse is exactly
  // -w), in the order and with the arithmetic of vertex_factor and geometry_term.
  Segment previous{Vec3(0.0f), 0.0f}, next{Vec3(0.0f), 0.0f};
  for (int i = 0; i <= k && f != DVec3(0.0); ++i) {
    const PathVertex& v = x[size_t(i)];
    if (i < k) next = segment_between(v, x[size_t(i + 1)]);
    const Vec3 w_light = -previous.w;
    f *= DVec3(vertex_factor_along(scene, v, i > 0 ? &w_light : nullptr, i < k ? &next.w : nullptr));
    if (i < k) f *= double(geometry_term_along(v, x[size_t(i + 1)], next));
    previous = next;
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
