#pragma once
// Wavefront OBJ meshes (tinyobjloader). Every object/group in the file is merged into one
// MeshDesc; polygons are fanned into triangles. The parts Mitsuba 0.6 makes separate meshes
// of (split at each `g`, and at each `usemtl` after faces) share no vertex, as in Mitsuba,
// unless `collapse` merges them into one as Mitsuba's collapse does.
#include <string>
#include <vector>

#include "emlt/scene/description.h"

namespace emlt {

// Positions are transformed by `to_world`, normals by its inverse transpose. The file's
// normals are used only when `smooth_normals` is set (area-weighted vertex normals are
// computed when the file has none); otherwise the mesh is flat shaded. Throws emlt::Error
// "<path>: <problem>" for a missing or unparsable file, out-of-range indices or no faces.
// Parser warnings are appended to `warnings` when given. Texture coordinates (`vt`) are
// kept when every corner has one; `flip_v` stores them as (u, 1 - v), the orientation
// the textures use (Mitsuba's flipTexCoords, on by default).
MeshDesc load_obj_mesh(const std::string& path, const Mat4& to_world, bool smooth_normals,
                       std::vector<std::string>* warnings = nullptr, bool flip_v = true);

// load_obj_mesh in two steps, the file's part (which a scene's loader may run ahead, in
// parallel: load_prefetch.h) and the placement: the mesh in the file's own space, the
// parser's warnings, and whether smooth normals are still to be computed (in world space).
struct ObjInFileSpace {
  MeshDesc mesh;
  std::vector<std::string> warnings;
  bool needs_smooth_normals = false;
  // The Mitsuba mesh each triangle belongs to (0, 1, ... in the file's order; all 0 when
  // collapsed), and the index of the last one, which Mitsuba creates at the file's end.
  std::vector<int> triangle_parts;
  int last_part = 0;
  // Whether the file names a material library (mtllib) that could be read.
  bool has_material_library = false;
};
ObjInFileSpace read_obj_file(const std::string& path, bool smooth_normals, bool flip_v,
                             bool collapse = false);
MeshDesc place_obj_mesh(ObjInFileSpace obj, const Mat4& to_world,
                        std::vector<std::string>* warnings);

// Mitsuba 0.6's `shapeIndex` of an OBJ: keeps the triangles of the meshes Mitsuba creates
// for it. Mitsuba creates mesh `shape_index` when the next part begins, and the file's last
// part when shape_index is one below the last part's index (so with one part, none).
void keep_obj_part(ObjInFileSpace& obj, int shape_index);

}  // namespace emlt
