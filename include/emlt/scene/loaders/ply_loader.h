#pragma once
// Stanford PLY meshes (ASCII, binary little and big endian), as Mitsuba 0.6's ply shape
// reads them: vertex x, y, z, optional nx, ny, nz and texture coordinates (u/v, s/t or
// texture_u/texture_v), per-vertex colours (red/green/blue or diffuse_red/..., uchar read
// as value / 255, float as it is; other types ignored with a warning, as Mitsuba never
// sees them), faces as a vertex_indices (or vertex_index) list. Polygons are
// fanned into triangles; every other element and property is skipped by its declared type.
#include <string>
#include <vector>

#include "emlt/scene/description.h"

namespace emlt {

// Positions are transformed by `to_world`, the file's normals (kept when it has them;
// none are computed here) by its inverse transpose. Unlike the serialized loader,
// Mitsuba's PLY loader keeps the winding under a mirroring transform, and so does this.
// Texture coordinates and colours are kept as stored. Throws emlt::Error "<path>: <problem>" for a
// missing file, a malformed header, truncated or unparsable data, counts the file cannot
// hold, indices out of range, or a file without faces. Faces with fewer than three
// vertices are skipped with a warning appended to `warnings` (when given).
MeshDesc load_ply_mesh(const std::string& path, const Mat4& to_world,
                       std::vector<std::string>* warnings = nullptr);

// load_ply_mesh in two steps: the file's part, which a scene's loader may run ahead in
// parallel (load_prefetch.h), and the placement.
MeshInFileSpace read_ply_file(const std::string& path);
MeshDesc place_ply_mesh(MeshInFileSpace ply, const Mat4& to_world,
                        std::vector<std::string>* warnings);

// The ply shape's `srgb` (true by default): the stored colours are sRGB-encoded, and each
// channel is decoded to linear by the sRGB curve, in single precision as Mitsuba does.
void decode_srgb_vertex_colors(MeshDesc& mesh);

}  // namespace emlt
