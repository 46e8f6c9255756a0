#pragma once
// Helpers shared by the JSON and Mitsuba XML loaders (internal to src/scene).
#include <optional>
#include <string>
#include <vector>

#include "emlt/scene/description.h"

namespace emlt::loader {

// Whole file as text; throws "<path>: cannot read file" when it cannot be opened.
std::string read_text_file(const std::string& path);

// `relative` interpreted against the scene file's directory (absolute paths unchanged);
// noted among the scene's input files (SceneDescription::input_files).
std::string resolve_path(const std::string& scene_file, const std::string& relative);

// Index of refraction for Mitsuba's named materials ("bk7", "water", "air", ...).
std::optional<float> named_ior(const std::string& name);

// Normal-incidence Fresnel reflectance of a conductor with complex IOR eta + i k.
Rgb conductor_normal_reflectance(const Rgb& eta, const Rgb& k);

// Fills env with a lat-long map read from `file` (already resolved); a missing file is
// reported against the scene file, an unreadable one against the map. A `gamma` replaces
// the file's own curve, as a Mitsuba bitmap's does (kSrgbGamma or an exponent; a float
// file's values are bent by it too).
void load_environment_map(EnvironmentDesc& env, const std::string& scene_file,
                          const std::string& file, std::optional<float> gamma = std::nullopt);

// Reads a cube map's six faces (files in the order +x, -x, +y, -y, +z, -z, resolved):
// square images of one size, else "<file>: ..." (cube_map_environment.h: conventions).
void load_cube_map(EnvironmentDesc& env, const std::string& scene_file,
                   const std::vector<std::string>& files);

// Rotation about `axis` by `degrees` (right-handed), as Mitsuba's <rotate>.
Mat4 rotation_matrix(const Vec3& axis, float degrees);

// Finds the material index of `bsdf` in desc.materials, adding it under `name` if new.
int material_index(SceneDescription& desc, const BsdfPtr& bsdf, const std::string& name);
// The same for a whole material (BSDF, opacity and bump must all match).
int material_index(SceneDescription& desc, const MaterialDesc& material);

// Sphere parameters after a transform: the center moves, the radius scales by the
// transform's mean axis scale (a warning is added when the scale is not uniform).
void transform_sphere(SphereDesc& sphere, const Mat4& to_world, const std::string& where,
                      std::vector<std::string>& warnings);

// The one check every mesh read from a file goes through (OBJ, serialized, PLY; from
// JSON and Mitsuba scenes alike), after its transform and normal computation: drops each
// triangle with a NaN or infinite position, normal or texture coordinate at a corner,
// and the vertices only those used. The normal computation skips such triangles, so the
// finite ones keep their normals. A drop is a warning and an unsupported divergence
// ("<file>: N triangles with non-finite vertices dropped"), so --strict refuses it;
// throws "<file>: ..." when it leaves the mesh with no triangle.
void drop_non_finite_triangles(SceneDescription& desc, MeshDesc& mesh, const std::string& file);

}  // namespace emlt::loader
