#include "emlt/scene/loaders/loader.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>

#include "emlt/core/error.h"
#include "emlt/image/image.h"
#include "emlt/scene/materials.h"
#include "src/scene/loaders/loader_common.h"

namespace emlt {

namespace {
// The files the loader on this thread resolves while it loads a scene (null when none).
thread_local std::vector<std::string>* t_input_files = nullptr;
}  // namespace

SceneDescription load_scene_description(const std::string& path, const SceneDefines& defines) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (extension != ".json" && extension != ".xml" && extension != ".pbrt")
    throw file_error(path, "unknown scene format (expected .json, Mitsuba .xml or pbrt-v4 .pbrt)");
  std::vector<std::string> inputs{path};
  t_input_files = &inputs;
  struct Forget {
    ~Forget() { t_input_files = nullptr; }
  } forget;
  SceneDescription desc = extension == ".json"   ? load_json_scene(path, defines)
                          : extension == ".pbrt" ? load_pbrt_scene(path)
                                                 : load_mitsuba_scene(path, defines);
  desc.input_files = std::move(inputs);
  return desc;
}

namespace loader {

std::string read_text_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw file_error(path, "file not found");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(path, "cannot read file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string resolve_path(const std::string& scene_file, const std::string& relative) {
  const std::filesystem::path p(relative);
  std::string resolved =
      p.is_absolute()
          ? p.lexically_normal().string()
          : (std::filesystem::path(scene_file).parent_path() / p).lexically_normal().string();
  if (t_input_files) t_input_files->push_back(resolved);
  return resolved;
}

std::optional<float> named_ior(const std::string& name) {
  // Mitsuba 0.6's table of named indices of refraction (at ~589 nm).
  static const std::pair<const char*, float> kTable[] = {
      {"vacuum", 1.0f},      {"helium", 1.000036f},        {"hydrogen", 1.000132f},
      {"air", 1.000277f},    {"carbon dioxide", 1.00045f}, {"water", 1.3330f},
      {"acetone", 1.36f},    {"ethanol", 1.361f},          {"carbon tetrachloride", 1.461f},
      {"glycerol", 1.4729f}, {"benzene", 1.501f},          {"silicone oil", 1.52045f},
      {"bromine", 1.661f},   {"water ice", 1.31f},         {"fused quartz", 1.458f},
      {"pyrex", 1.470f},     {"acrylic glass", 1.49f},     {"polypropylene", 1.49f},
      {"bk7", 1.5046f},      {"sodium chloride", 1.544f},  {"amber", 1.55f},
      {"pet", 1.5750f},      {"diamond", 2.419f},          {"glass", 1.5f}};
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  for (const auto& [key, value] : kTable)
    if (lower == key) return value;
  return std::nullopt;
}

Rgb conductor_normal_reflectance(const Rgb& eta, const Rgb& k) {
  const Rgb k2 = k * k;
  const Rgb numerator = (eta - 1.0f) * (eta - 1.0f) + k2;
  const Rgb denominator = (eta + 1.0f) * (eta + 1.0f) + k2;
  return glm::clamp(numerator / glm::max(denominator, Rgb(1e-12f)), Rgb(0.0f), Rgb(1.0f));
}

void load_environment_map(EnvironmentDesc& env, const std::string& scene_file,
                          const std::string& file, std::optional<float> gamma) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw file_error(scene_file, "environment map '" + file + "' not found");
  env.kind = EnvironmentDesc::Kind::Map;
  env.map_path = file;
  if (gamma && is_stored_image(file)) {
    env.map = decode_stored_image(read_stored_image(file), *gamma);
    return;
  }
  env.map = read_image(file);
  if (gamma && *gamma != 1.0f)
    for (Rgb& texel : env.map.pixels)
      texel = Rgb(decode_gamma(texel.x, *gamma), decode_gamma(texel.y, *gamma),
                  decode_gamma(texel.z, *gamma));
}

void load_cube_map(EnvironmentDesc& env, const std::string& scene_file,
                   const std::vector<std::string>& files) {
  if (files.size() != 6)
    throw file_error(scene_file, "a cube map needs six faces (+x, -x, +y, -y, +z, -z), got " +
                                     std::to_string(files.size()));
  env.kind = EnvironmentDesc::Kind::CubeMap;
  env.cube_faces.clear();
  for (const std::string& file : files) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
      throw file_error(scene_file, "cube map face '" + file + "' not found");
    Image face = read_image(file);
    if (face.width != face.height)
      throw file_error(file, "a cube map face must be square (" + std::to_string(face.width) +
                                 " x " + std::to_string(face.height) + ")");
    if (!env.cube_faces.empty() && face.width != env.cube_faces.front().width)
      throw file_error(file, "the cube map's faces differ in size (" +
                                 std::to_string(face.width) + " against " +
                                 std::to_string(env.cube_faces.front().width) + ")");
    env.cube_faces.push_back(std::move(face));
  }
}

Mat4 rotation_matrix(const Vec3& axis, float degrees) {
  const float length = glm::length(axis);
  if (!(length > 0.0f)) return Mat4(std::numeric_limits<float>::quiet_NaN());
  return glm::rotate(Mat4(1.0f), glm::radians(degrees), axis / length);
}

int material_index(SceneDescription& desc, const BsdfPtr& bsdf, const std::string& name) {
  return material_index(desc, MaterialDesc(name, bsdf));
}

int material_index(SceneDescription& desc, const MaterialDesc& material) {
  for (size_t i = 0; i < desc.materials.size(); ++i) {
    const MaterialDesc& m = desc.materials[i];
    if (m.bsdf == material.bsdf && m.opacity == material.opacity && m.bump == material.bump)
      return int(i);
  }
  desc.materials.push_back(material);
  return int(desc.materials.size() - 1);
}

void transform_sphere(SphereDesc& sphere, const Mat4& to_world, const std::string& where,
                      std::vector<std::string>& warnings) {
  sphere.center = Vec3(to_world * Vec4(sphere.center, 1.0f));
  const Vec3 scales(glm::length(Vec3(to_world[0])), glm::length(Vec3(to_world[1])),
                    glm::length(Vec3(to_world[2])));
  const float mean = (scales.x + scales.y + scales.z) / 3.0f;
  if (std::abs(scales.x - mean) > 1e-4f * mean || std::abs(scales.y - mean) > 1e-4f * mean ||
      std::abs(scales.z - mean) > 1e-4f * mean)
    warnings.push_back(where + ": non-uniform scale on a sphere; using the mean scale");
  sphere.radius *= mean;
}

void drop_non_finite_triangles(SceneDescription& desc, MeshDesc& mesh, const std::string& file) {
  const bool has_normals = mesh.normals.size() == mesh.positions.size();
  const bool has_uvs = mesh.uvs.size() == mesh.positions.size();
  const bool has_colors = mesh.colors.size() == mesh.positions.size();
  auto finite_vertex = [&](uint32_t v) {
    // Indices out of range are Scene::build's to report; they are kept here.
    return v >= mesh.positions.size() ||
           (is_finite(mesh.positions[v]) && (!has_normals || is_finite(mesh.normals[v])) &&
            (!has_uvs || (std::isfinite(mesh.uvs[v].x) && std::isfinite(mesh.uvs[v].y))));
  };
  // Nearly every mesh is finite throughout: one pass over its vertices settles that without
  // copying its indices.
  bool all_finite = true;
  for (uint32_t v = 0; all_finite && v < uint32_t(mesh.positions.size()); ++v)
    all_finite = finite_vertex(v);
  if (all_finite) return;
  std::vector<uint32_t> kept;
  kept.reserve(mesh.indices.size());
  size_t dropped = 0;
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const uint32_t* corner = &mesh.indices[i];
    if (finite_vertex(corner[0]) && finite_vertex(corner[1]) && finite_vertex(corner[2]))
      kept.insert(kept.end(), corner, corner + 3);
    else
      ++dropped;
  }
  if (dropped == 0) return;
  if (kept.empty())
    throw file_error(file, "every triangle (" + std::to_string(dropped) +
                               ") has a NaN or infinite vertex position, normal or texture "
                               "coordinate; no triangle is left");

  // Renumber the vertices still used, so that no non-finite one reaches the scene (a
  // planar uv projection, for one, spans every vertex of a mesh).
  constexpr uint32_t kUnused = UINT32_MAX;
  std::vector<uint32_t> renumbered(mesh.positions.size(), kUnused);
  MeshDesc compact;
  for (uint32_t& v : kept) {
    if (v >= mesh.positions.size()) continue;
    if (renumbered[v] == kUnused) {
      renumbered[v] = uint32_t(compact.positions.size());
      compact.positions.push_back(mesh.positions[v]);
      if (has_normals) compact.normals.push_back(mesh.normals[v]);
      if (has_uvs) compact.uvs.push_back(mesh.uvs[v]);
      if (has_colors) compact.colors.push_back(mesh.colors[v]);
    }
    v = renumbered[v];
  }
  mesh.positions = std::move(compact.positions);
  if (has_normals) mesh.normals = std::move(compact.normals);
  if (has_uvs) mesh.uvs = std::move(compact.uvs);
  if (has_colors) mesh.colors = std::move(compact.colors);
  mesh.indices = std::move(kept);

  const std::string message = file + ": " + std::to_string(dropped) +
                              " triangles with non-finite vertices dropped (a NaN or infinite "
                              "position, normal or texture coordinate)";
  desc.warnings.push_back(message);
  desc.divergences.push_back({Divergence::Kind::Unsupported, message});
}

}  // namespace loader
}  // namespace emlt
