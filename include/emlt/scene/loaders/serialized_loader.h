#pragma once
// Mitsuba 0.6's own mesh format (.serialized): a sequence of meshes, each a 4-byte header
// (0x041C, format version 3 or 4) followed by a zlib stream holding flags, [name (v4)],
// vertex and triangle counts, positions, optional normals, texture coordinates and
// colours (single or double precision) and the triangles' uint32 indices. A dictionary of
// the meshes' offsets ends the file.
#include <string>
#include <vector>

#include "emlt/scene/description.h"

namespace emlt {

// Mesh number `shape_index` of the file. Positions are transformed by `to_world`, the
// file's normals (kept when it has them; none are computed here) by its inverse
// transpose; a mirroring transform reverses the winding so the facing is kept, as
// Mitsuba does. Texture coordinates are kept as stored; vertex colours are skipped.
// Throws emlt::Error "<path>: <problem>" for a missing, truncated or corrupt file, an
// unknown header or version, counts the file cannot hold, indices out of range or
// `shape_index` out of range. A mesh without triangles is returned empty.
MeshDesc load_serialized_mesh(const std::string& path, int shape_index, const Mat4& to_world);

// load_serialized_mesh in two steps: the file's part, which a scene's loader may run ahead
// in parallel (load_prefetch.h), giving the mesh in the file's own space, and its placement.
MeshDesc read_serialized_mesh(const std::string& path, int shape_index);
MeshDesc place_serialized_mesh(MeshDesc mesh, const Mat4& to_world);

}  // namespace emlt
