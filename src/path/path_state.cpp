#include "emlt/path/path_state.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "emlt/core/error.h"
#include "emlt/scene/directional_light.h"

namespace emlt {

namespace {
bool is_finite(const Vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
// Normals, frames and sky directions are unit vectors up to float rounding.
bool is_unit(const Vec3& v) { return std::abs(glm::length(v) - 1.0f) <= 1e-2f; }
}  // namespace
using emlt::is_finite;

PathCodec::PathCodec(const Scene& scene) : scene_(scene) {
  for (const MaterialDesc& m : scene.description().materials) {
    const Bsdf* bsdf = m.bsdf.get();
    if (bsdf && !bsdf_index_.contains(bsdf)) {
      bsdf_index_[bsdf] = int32_t(bsdfs_.size());
      bsdfs_.push_back(bsdf);
    }
  }
  for (size_t i = 0; i < scene.lights().size(); ++i)
    light_index_[&scene.lights().light(i)] = int32_t(i);
}

void PathCodec::save(const Path& path, StateWriter& out) const {
  out.put<uint64_t>(path.type.specular_mask);
  out.put<uint8_t>(path.type.vertices);
  out.put<uint64_t>(path.vertices.size());
  for (const PathVertex& v : path.vertices) {
    int32_t bsdf = -1, light = -1;
    if (v.bsdf) {
      const auto it = bsdf_index_.find(v.bsdf);
      if (it == bsdf_index_.end()) throw Error("a path vertex's BSDF is not one of the scene's");
      bsdf = it->second;
    }
    if (v.light) {
      const auto it = light_index_.find(v.light);
      if (it == light_index_.end()) throw Error("a path vertex's light is not one of the scene's");
      light = it->second;
    }
    out.put<uint8_t>(uint8_t(v.kind));
    out.put<uint8_t>(v.delta);
    out.put(v.position);
    out.put(v.normal);
    out.put(v.shading.s);
    out.put(v.shading.t);
    out.put(v.shading.n);
    out.put(v.uv);
    // Only where some mesh has colours, so that other scenes' checkpoints keep their layout.
    if (scene_.has_vertex_colors()) out.put(v.vertex_color);
    out.put(v.sky_direction);
    out.put(bsdf);
    out.put(light);
    out.put(v.throughput);
    out.put(v.pdf_from_light);
    out.put(v.pdf_from_eye);
    out.put(v.delta_probability);
    out.put(v.delta_value);
    out.put(v.delta_ior_ratio);
    out.put(v.raster);
  }
}

Path PathCodec::load(StateReader& in) const {
  Path path;
  path.type.specular_mask = in.get<uint64_t>();
  path.type.vertices = in.get<uint8_t>();
  const uint64_t count = in.get<uint64_t>();
  if (count > uint64_t(kMaxPathVertices)) throw StateError("a saved path is longer than possible");
  path.vertices.resize(count);
  // Generous: twice as far as the camera or the farthest surface, whichever is farther.
  const float reach =
      2.0f * (scene_.bounds_radius() +
              glm::length(scene_.camera().position() - scene_.bounds_center()));
  for (PathVertex& v : path.vertices) {
    const uint8_t kind = in.get<uint8_t>();
    if (kind > uint8_t(VertexKind::OrthographicCamera))
      throw StateError("a saved path vertex has no known kind");
    v.kind = VertexKind(kind);
    v.delta = in.get<uint8_t>() != 0;
    v.position = in.get<Vec3>();
    v.normal = in.get<Vec3>();
    v.shading.s = in.get<Vec3>();
    v.shading.t = in.get<Vec3>();
    v.shading.n = in.get<Vec3>();
    v.uv = in.get<Vec2>();
    if (scene_.has_vertex_colors()) v.vertex_color = in.get<Rgb>();
    v.sky_direction = in.get<Vec3>();
    const int32_t bsdf = in.get<int32_t>(), light = in.get<int32_t>();
    if (bsdf < -1 || bsdf >= int32_t(bsdfs_.size()))
      throw StateError("a saved path vertex names a material this scene does not have");
    if (light < -1 || light >= int32_t(scene_.lights().size()))
      throw StateError("a saved path vertex names a light this scene does not have");
    v.bsdf = bsdf >= 0 ? bsdfs_[size_t(bsdf)] : nullptr;
    v.light = light >= 0 ? &scene_.lights().light(size_t(light)) : nullptr;
    v.throughput = in.get<Rgb>();
    v.pdf_from_light = in.get<float>();
    v.pdf_from_eye = in.get<float>();
    v.delta_probability = in.get<float>();
    v.delta_value = in.get<Rgb>();
    v.delta_ior_ratio = in.get<float>();
    v.raster = in.get<Vec2>();
    const bool finite = is_finite(v.position) && is_finite(v.normal) && is_finite(v.shading.s) &&
                        is_finite(v.shading.t) && is_finite(v.shading.n) && is_finite(v.uv) &&
                        is_finite(v.vertex_color) && is_finite(v.sky_direction) &&
                        is_finite(v.throughput) && std::isfinite(v.pdf_from_light) &&
                        std::isfinite(v.pdf_from_eye) && std::isfinite(v.delta_probability) &&
                        is_finite(v.delta_value) && std::isfinite(v.delta_ior_ratio) &&
                        is_finite(v.raster);
    if (!finite) throw StateError("a saved path vertex holds a value that is not a number");
    // A delta light's vertex is its light's one point or direction (and only such a
    // light's vertex is of those kinds): mutations never move it.
    const bool point = v.kind == VertexKind::PointEmitter;
    const bool distant = v.kind == VertexKind::DistantEmitter;
    bool light_ok = !v.light || !v.light->is_delta();
    if (point)
      light_ok = v.light && v.light->is_delta_position() &&
                 v.position == v.light->delta_point();
    if (distant)
      light_ok = v.light && v.light->is_delta_direction() &&
                 v.sky_direction == static_cast<const DirectionalLight*>(v.light)->towards_light();
    if (!light_ok) throw StateError("a saved path vertex does not match its delta light");
    // A camera vertex is of the scene camera's kind; an orthographic camera's lies on its
    // film (the projection of the vertex it sees: a point off the film would be seen along
    // no ray, and weighted as if it were).
    if (v.is_camera()) {
      const Camera& camera = scene_.camera();
      if ((v.kind == VertexKind::OrthographicCamera) != camera.is_orthographic())
        throw StateError("a saved camera vertex is not of this scene's camera");
      if (camera.is_orthographic() && !camera.on_film(v.position))
        throw StateError("a saved camera vertex does not lie on the orthographic camera's film");
    }
    // Mutations trace rays from these points along directions made of these vectors: a
    // normal of length 1e27 or a point far beyond the scene made rays Embree refuses (it
    // asserts), a vector of no length is normalised into NaN. Points lie within the scene's
    // bounds or on the lens; a point light has no directions, and may lie anywhere.
    const bool directions_ok =
        v.is_environment() ? is_unit(v.sky_direction)
                           : point || (is_unit(v.normal) && is_unit(v.shading.s) &&
                                       is_unit(v.shading.t) && is_unit(v.shading.n));
    if (!directions_ok)
      throw StateError("a saved path vertex has a normal or direction that is not of unit length");
    // (An orthographic film point was checked above: on the film, which may reach further.)
    if (!v.is_environment() && !point && v.kind != VertexKind::OrthographicCamera &&
        !(glm::length(v.position - scene_.bounds_center()) <= reach))
      throw StateError("a saved path vertex lies outside the scene");
  }
  // The shape every path of the chains has: an emitter or the sky first, the lens last,
  // surfaces with a BSDF between (what the mutations rely on), and the type that follows
  // from its vertices (which mutations apply, and EMLT's guides, go by it).
  if (count > 0) {
    const bool shape_ok =
        count >= 2 && path.type == compute_path_type(path.vertices) &&
        path.vertices.back().is_camera() && !path.vertices.front().is_camera() &&
        std::all_of(path.vertices.begin() + 1, path.vertices.end() - 1,
                    [](const PathVertex& v) { return v.is_surface() && v.bsdf != nullptr; });
    if (!shape_ok) throw StateError("a saved path is not a path from a light to the camera");
    for (size_t i = 1; i < count; ++i)
      if (!path.vertices[i - 1].is_environment() &&
          path.vertices[i - 1].position == path.vertices[i].position)
        throw StateError("a saved path has an edge of no length");
    // The chains find the path's film pixel from its raster position (clamped there, so the
    // image's far edges pass, but first converted to int, which a value far outside would
    // overflow).
    const Vec2 raster = path.raster();
    const float width = float(scene_.camera().width()), height = float(scene_.camera().height());
    if (!(raster.x >= 0.0f && raster.x <= width && raster.y >= 0.0f && raster.y <= height))
      throw StateError("a saved path lands outside the image");
  }
  return path;
}

void PathCodec::pack(const Path& path, StateWriter& out) const {
  out.put(path.type);
  out.put_vector(path.vertices);
  for (const PathVertex& v : path.vertices) {
    out.put<int32_t>(v.bsdf ? bsdf_index_.at(v.bsdf) : -1);
    out.put<int32_t>(v.light ? light_index_.at(v.light) : -1);
  }
}

void PathCodec::unpack(StateReader& in, Path& path) const {
  path.type = in.get<PathType>();
  in.get_vector_into(path.vertices, uint64_t(kMaxPathVertices));
  for (PathVertex& v : path.vertices) {
    const int32_t bsdf = in.get<int32_t>(), light = in.get<int32_t>();
    v.bsdf = bsdf >= 0 ? bsdfs_.at(size_t(bsdf)) : nullptr;
    v.light = light >= 0 ? &scene_.lights().light(size_t(light)) : nullptr;
  }
}

namespace {
// One vertex of the guide form (trivially copyable, written as raw bytes).
struct GuideVertex {
  Vec3 position;
  Vec3 sky_direction;
  uint32_t kind;
};
}  // namespace

void PathCodec::pack_guide(const Path& path, StateWriter& out) {
  out.put(path.type);
  out.put<uint8_t>(uint8_t(path.vertices.size()));  // at most kMaxPathVertices
  if (path.vertices.empty()) return;
  GuideVertex records[kMaxPathVertices];
  for (size_t i = 0; i < path.vertices.size(); ++i) {
    const PathVertex& v = path.vertices[i];
    records[i] = GuideVertex{v.position, v.sky_direction, uint32_t(v.kind)};
  }
  out.put_string(std::string_view(reinterpret_cast<const char*>(records),
                                  path.vertices.size() * sizeof(GuideVertex)));
  out.put(path.raster());
}

void PathCodec::unpack_guide(StateReader& in, Path& path) {
  path.type = in.get<PathType>();
  const size_t count = in.get<uint8_t>();
  path.vertices.assign(count, PathVertex{});
  if (count == 0) return;
  const std::string_view bytes = in.get_block();
  if (bytes.size() != count * sizeof(GuideVertex)) throw StateError("a guide path is damaged");
  for (size_t i = 0; i < count; ++i) {
    GuideVertex record;
    std::memcpy(&record, bytes.data() + i * sizeof(GuideVertex), sizeof(GuideVertex));
    PathVertex& v = path.vertices[i];
    v.kind = VertexKind(record.kind);
    v.position = record.position;
    v.sky_direction = record.sky_direction;
  }
  path.vertices.back().raster = in.get<Vec2>();
}

}  // namespace emlt
