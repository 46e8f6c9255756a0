#include "emlt/scene/loaders/obj_loader.h"

#include <tiny_obj_loader.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "emlt/core/error.h"
#include "emlt/scene/shape_builders.h"

namespace emlt {

namespace {

// tinyobjloader reports problems as multi-line text; messages here are single lines.
std::string first_line(const std::string& text) {
  std::istringstream stream(text);
  std::string line;
  while (std::getline(stream, line))
    if (!line.empty()) return line;
  return text;
}

// tinyobjloader reads "nan" and "inf" as 0 without a word, which moves a vertex instead
// of flagging it. This re-reads the v, vn and vt lines and puts back each coordinate
// that strtod reads as NaN or infinite, so that the loader's non-finite check
// (loader::drop_non_finite_triangles) sees it. Left alone when the counts disagree with
// tinyobjloader's (a line format this scan does not follow). Lines and words are split as
// std::getline and operator>> would split them, but in place over the file's bytes: the
// stream version cost twice tinyobjloader's own parse (200 M instructions of loading the
// public Veach door).
void restore_non_finite(const std::string& path, std::vector<float>& vertices,
                        std::vector<float>& normals, std::vector<float>& texcoords) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  struct Kind {
    std::string_view tag;
    std::vector<float>* values;
    size_t per_line;
    std::vector<std::pair<size_t, float>> found;
    size_t lines = 0;
  } kinds[] = {
      {"v", &vertices, 3, {}, 0}, {"vn", &normals, 3, {}, 0}, {"vt", &texcoords, 2, {}, 0}};
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  const char* const end = text.data() + text.size();
  for (const char* line = text.data(); line < end;) {
    const char* line_end = static_cast<const char*>(std::memchr(line, '\n', size_t(end - line)));
    if (!line_end) line_end = end;
    const char* p = line;
    // The next word of the line: [p, word_end), after blanks (a newline ends the line).
    const auto next_word = [&]() -> std::string_view {
      while (p < line_end && blank(*p)) ++p;
      const char* word = p;
      while (p < line_end && !blank(*p)) ++p;
      return std::string_view(word, size_t(p - word));
    };
    const std::string_view tag = next_word();
    for (Kind& kind : kinds) {
      if (tag != kind.tag) continue;
      for (size_t k = 0; k < kind.per_line; ++k) {
        const std::string_view word = next_word();
        if (word.empty()) break;
        // Only "nan", "inf" (any case) and an overflow (an exponent, or hundreds of digits)
        // can read as non-finite: plain decimals skip strtod, the scan's main cost.
        if (word.size() < 300 && word.find_first_of("nNiIeEpP") == std::string_view::npos) continue;
        // strtod stops at the blank (or the newline) after the word, as on a copy of it.
        const double value = std::strtod(word.data(), nullptr);
        if (!std::isfinite(value))
          kind.found.emplace_back(kind.lines * kind.per_line + k, float(value));
      }
      ++kind.lines;
    }
    line = line_end + 1;
  }
  for (Kind& kind : kinds) {
    if (kind.lines * kind.per_line != kind.values->size()) continue;
    for (const auto& [at, value] : kind.found) (*kind.values)[at] = value;
  }
}

// The Mitsuba mesh of each face line ("f"), in order, as Mitsuba 0.6's OBJ reader splits
// the file: a `g` after faces, or a `usemtl` after faces, ends a mesh (neither when
// collapsed); and the index of the last mesh.
std::pair<std::vector<int>, int> mitsuba_parts_of_faces(const std::string& path, bool collapse) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<int> parts;
  int part = 0;
  bool faces_since_split = false;
  const char* const end = text.data() + text.size();
  for (const char* line = text.data(); line < end;) {
    const char* line_end = static_cast<const char*>(std::memchr(line, '\n', size_t(end - line)));
    if (!line_end) line_end = end;
    const char* p = line;
    while (p < line_end && std::isspace(static_cast<unsigned char>(*p))) ++p;
    const char* word = p;
    while (p < line_end && !std::isspace(static_cast<unsigned char>(*p))) ++p;
    const std::string_view tag(word, size_t(p - word));
    if (tag == "f") {
      parts.push_back(part);
      faces_since_split = true;
    } else if ((tag == "g" || tag == "usemtl") && !collapse && faces_since_split) {
      ++part;
      faces_since_split = false;
    }
    line = line_end + 1;
  }
  return {parts, part};
}

}  // namespace

void keep_obj_part(ObjInFileSpace& obj, int shape_index) {
  if (shape_index < 0) return;
  const auto kept = [&](int part) {
    return (part == shape_index && part < obj.last_part) ||
           (part == obj.last_part && shape_index == obj.last_part - 1);
  };
  MeshDesc& mesh = obj.mesh;
  std::vector<uint32_t> indices;
  std::vector<int> parts;
  for (size_t t = 0; t < obj.triangle_parts.size(); ++t) {
    if (!kept(obj.triangle_parts[t])) continue;
    indices.insert(indices.end(), mesh.indices.begin() + std::ptrdiff_t(3 * t),
                   mesh.indices.begin() + std::ptrdiff_t(3 * t + 3));
    parts.push_back(obj.triangle_parts[t]);
  }
  // The vertices the kept triangles use, renumbered in order.
  std::vector<uint32_t> renumbered(mesh.positions.size(), UINT32_MAX);
  MeshDesc kept_mesh;
  kept_mesh.name = mesh.name;
  for (uint32_t& index : indices) {
    if (renumbered[index] == UINT32_MAX) {
      renumbered[index] = uint32_t(kept_mesh.positions.size());
      kept_mesh.positions.push_back(mesh.positions[index]);
      if (!mesh.normals.empty()) kept_mesh.normals.push_back(mesh.normals[index]);
      if (!mesh.uvs.empty()) kept_mesh.uvs.push_back(mesh.uvs[index]);
    }
    index = renumbered[index];
  }
  kept_mesh.indices = std::move(indices);
  mesh = std::move(kept_mesh);
  obj.triangle_parts = std::move(parts);
}

MeshDesc load_obj_mesh(const std::string& path, const Mat4& to_world, bool smooth_normals,
                       std::vector<std::string>* warnings, bool flip_v) {
  return place_obj_mesh(read_obj_file(path, smooth_normals, flip_v), to_world, warnings);
}

MeshDesc place_obj_mesh(ObjInFileSpace obj, const Mat4& to_world,
                        std::vector<std::string>* warnings) {
  if (warnings) warnings->insert(warnings->end(), obj.warnings.begin(), obj.warnings.end());
  transform_mesh(obj.mesh, to_world, false);
  if (obj.needs_smooth_normals) compute_smooth_normals(obj.mesh);
  return std::move(obj.mesh);
}

ObjInFileSpace read_obj_file(const std::string& path, bool smooth_normals, bool flip_v,
                             bool collapse) {
  ObjInFileSpace result;
  std::vector<std::string>* warnings = &result.warnings;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw file_error(path, "OBJ file not found");

  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // fanned below, after the indices have been validated
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config))
    throw file_error(path, "OBJ parse error: " + first_line(reader.Error()));
  if (warnings && !reader.Warning().empty()) {
    std::istringstream stream(reader.Warning());
    std::string line;
    while (std::getline(stream, line))
      if (!line.empty() && line.find("out of bounds") == std::string::npos)
        warnings->push_back(path + ": " + line);
  }

  result.has_material_library = !reader.GetMaterials().empty();
  tinyobj::attrib_t attrib = reader.GetAttrib();
  restore_non_finite(path, attrib.vertices, attrib.normals, attrib.texcoords);
  const auto vertex_count = int(attrib.vertices.size() / 3);
  const auto normal_count = int(attrib.normals.size() / 3);
  const auto uv_count = int(attrib.texcoords.size() / 2);

  // The file's normals are used only if every corner has one; uvs likewise.
  bool use_file_normals = smooth_normals, use_uvs = true;
  size_t face_count = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const std::string object = shape.name.empty() ? "" : " (object '" + shape.name + "')";
    size_t corner = 0;
    for (size_t face = 0; face < shape.mesh.num_face_vertices.size(); ++face) {
      const int n = shape.mesh.num_face_vertices[face];
      for (int k = 0; k < n; ++k) {
        const tinyobj::index_t& index = shape.mesh.indices[corner + k];
        if (index.vertex_index < 0 || index.vertex_index >= vertex_count)
          throw file_error(path, "face " + std::to_string(face_count + 1) + object +
                                     " uses vertex " + std::to_string(index.vertex_index + 1) +
                                     ", out of range (" + std::to_string(vertex_count) +
                                     " vertices)");
        if (index.normal_index >= normal_count || index.texcoord_index >= uv_count)
          throw file_error(path, "face " + std::to_string(face_count + 1) + object +
                                     " uses a normal or texture index out of range");
        use_file_normals &= index.normal_index >= 0;
        use_uvs &= index.texcoord_index >= 0;
      }
      corner += size_t(n);
      if (n >= 3) ++face_count;
    }
  }
  if (face_count == 0) throw file_error(path, "OBJ has no faces");

  // Mitsuba's meshes of the file, face by face; one, when the scan and tinyobjloader
  // disagree on the faces (a line format the scan does not follow).
  size_t face_lines = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes())
    face_lines += shape.mesh.num_face_vertices.size();
  auto [face_parts, last_part] = mitsuba_parts_of_faces(path, collapse);
  if (face_parts.size() != face_lines) {
    face_parts.assign(face_lines, 0);
    last_part = 0;
  }
  result.last_part = last_part;

  MeshDesc& mesh = result.mesh;
  mesh.name = std::filesystem::path(path).filename().string();
  // Corners sharing position (and normal/uv where used) become one vertex, within one of
  // Mitsuba's meshes.
  std::map<std::tuple<int, int, int, int>, uint32_t> vertex_of_corner;
  int part = 0;
  auto vertex_for = [&](const tinyobj::index_t& index) {
    const auto key =
        std::make_tuple(part, index.vertex_index, use_file_normals ? index.normal_index : -1,
                        use_uvs ? index.texcoord_index : -1);
    auto [it, inserted] = vertex_of_corner.try_emplace(key, uint32_t(mesh.positions.size()));
    if (inserted) {
      const float* p = &attrib.vertices[3 * size_t(index.vertex_index)];
      mesh.positions.push_back(Vec3(p[0], p[1], p[2]));
      if (use_file_normals) {
        const float* n = &attrib.normals[3 * size_t(index.normal_index)];
        mesh.normals.push_back(Vec3(n[0], n[1], n[2]));
      }
      if (use_uvs) {
        const float* t = &attrib.texcoords[2 * size_t(index.texcoord_index)];
        mesh.uvs.push_back(Vec2(t[0], flip_v ? 1.0f - t[1] : t[1]));
      }
    }
    return it->second;
  };

  size_t face_line = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    size_t corner = 0;
    for (const unsigned char n : shape.mesh.num_face_vertices) {
      part = face_parts[face_line++];
      if (n >= 3) {
        const uint32_t first = vertex_for(shape.mesh.indices[corner]);
        for (int k = 1; k + 1 < n; ++k) {
          mesh.indices.insert(mesh.indices.end(),
                              {first, vertex_for(shape.mesh.indices[corner + k]),
                               vertex_for(shape.mesh.indices[corner + k + 1])});
          result.triangle_parts.push_back(part);
        }
      }
      corner += n;
    }
  }

  result.needs_smooth_normals = smooth_normals && !use_file_normals;
  return result;
}

}  // namespace emlt
