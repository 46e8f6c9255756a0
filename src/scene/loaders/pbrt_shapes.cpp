// pbrt-v4's shapes: triangle and PLY meshes, bilinear patches (as two triangles each),
// spheres (analytic), disks and cylinders (tessellated). A shape faces the way pbrt's does:
// a mesh without normals by its winding in object space (a mirroring transform keeps it),
// with normals by them; ReverseOrientation turns it. pbrt's area lights emit on that side.
#include <fmt/format.h>

#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>

#include "emlt/scene/loaders/ply_loader.h"
#include "emlt/scene/shape_builders.h"
#include "src/scene/loaders/loader_common.h"
#include "src/scene/loaders/pbrt_reader.h"

namespace emlt::pbrt {

namespace {

// Indices checked against the vertex count, in groups of `corners`; empty when the file
// gives none and has more vertices than one primitive.
std::vector<int> read_indices(const Params& params, size_t vertices, size_t corners,
                              const char* shape) {
  std::vector<int> indices = params.get_ints("indices");
  const Param* p = params.get("indices");
  if (!p) {
    if (vertices != corners) return {};
    for (size_t i = 0; i < corners; ++i) indices.push_back(int(i));
    return indices;
  }
  if (indices.empty() || indices.size() % corners != 0)
    Params::fail(*p, fmt::format("a {} needs a multiple of {} indices", shape, corners));
  for (int i : indices)
    if (i < 0 || size_t(i) >= vertices)
      Params::fail(*p,
                   fmt::format("index {} out of range (the mesh has {} vertices)", i, vertices));
  return indices;
}

}  // namespace

void Reader::place_sphere(const Where& at, SphereDesc& sphere, const Mat4& to_world) {
  std::vector<std::string> uneven;
  loader::transform_sphere(sphere, to_world, at.file + ": line " + std::to_string(at.line), uneven);
  if (!uneven.empty())
    warn(at, "a sphere under a non-uniform scale is not supported; its mean scale is used",
         Divergence::Kind::Approximated);
  if (!is_finite(sphere.center) || !std::isfinite(sphere.radius) || !(sphere.radius > 0.0f))
    fail(at, "the sphere's transformed center or radius is not finite");
}

void Reader::shape(const Where& at, const std::string& type, const Params& params) {
  const std::string what = "Shape \"" + type + "\"";
  if (state_.interface) {
    // An interface material marks a boundary between media; pbrt renders no surface there.
    for (const Param* p : params.unused()) p->used = true;
    note(at, what + " with the \"interface\" material bounds media only; no surface is made");
    return;
  }
  int material = state_.material >= 0 ? state_.material : default_material();
  Rgb emission(0.0f);
  if (state_.area_light) {
    if (current_object_)
      warn(at, what +
                   ": an area light inside ObjectBegin is not supported (nor by pbrt); the "
                   "shape does not emit");
    else
      emission = *state_.area_light;
  }
  if (const Param* alpha = params.get("alpha")) {
    TexturePtr opacity = texture(params, "alpha", Rgb(1.0f), true);
    const std::optional<Rgb> constant = opacity->constant();
    if (!constant || (*constant != Rgb(1.0f))) {
      MaterialDesc cut = desc_.materials[size_t(material)];
      cut.opacity = opacity;
      cut.textured = cut.textured || !constant;
      cut.name += fmt::format(" (alpha at line {})", alpha->line);
      material = loader::material_index(desc_, cut);
    }
  }
  for (const char* name : {"emissionfilename", "displacement", "edgelength"})
    if (const Param* p = params.get(name))
      warn({p->file, p->line}, what + " " + p->quoted() + " is not supported; ignored");
  const Mat4& ctm = state_.ctm;
  if (!is_finite_matrix(ctm)) fail(at, what + ": the transformation has NaN or infinity");
  const std::string name = type + " at " + std::filesystem::path(at.file).filename().string() +
                           ":" + std::to_string(at.line);

  if (type == "sphere") {
    SphereDesc sphere;
    sphere.name = name;
    sphere.radius = params.get_float("radius", 1.0f);
    if (!(sphere.radius > 0.0f)) Params::fail(*params.get("radius"), "must be positive");
    const float zmin = params.get_float("zmin", -sphere.radius),
                zmax = params.get_float("zmax", sphere.radius),
                phimax = params.get_float("phimax", 360.0f);
    if (zmin > -sphere.radius || zmax < sphere.radius || phimax < 360.0f)
      warn(at, what +
                   ": a partial sphere (zmin, zmax, phimax) is not supported; the whole "
                   "sphere is used");
    place_sphere(at, sphere, ctm);
    sphere.material = material;
    sphere.emission = emission;
    sphere.flip_normals = state_.reverse_orientation;
    report_unused(params, what);
    (current_object_ ? current_object_->spheres : desc_.spheres).push_back(sphere);
    return;
  }

  MeshDesc mesh;  // in object space
  if (type == "trianglemesh" || type == "bilinearmesh") {
    const bool bilinear = type == "bilinearmesh";
    mesh.positions = params.get_vec3s("P", "point3");
    if (mesh.positions.empty()) fail(at, what + " needs 'point3 P'");
    const std::vector<int> indices =
        read_indices(params, mesh.positions.size(), bilinear ? 4 : 3, type.c_str());
    if (indices.empty())
      fail(at, what + " needs 'integer indices' (only a single " +
                   (bilinear ? "patch of 4" : "triangle of 3") + " vertices may omit them)");
    mesh.normals = params.get_vec3s("N", "normal");
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
      Params::fail(*params.get("N"), fmt::format("{} normals for {} vertices", mesh.normals.size(),
                                                 mesh.positions.size()));
    mesh.uvs = params.get_point2s("uv");
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
      Params::fail(*params.get("uv"), fmt::format("{} texture coordinates for {} vertices",
                                                  mesh.uvs.size(), mesh.positions.size()));
    if (params.has("S"))
      note(at, what + ": tangents 'S' ignored (emlt derives its shading frames from uv)");
    params.ignore("S");
    params.ignore("faceIndices");
    if (!bilinear) {
      mesh.indices.assign(indices.begin(), indices.end());
    } else {
      // pbrt's patch (p00, p10, p01, p11) as the triangles (p00, p10, p11) and (p00, p11,
      // p01), which face as the patch's dp/du x dp/dv does; exact where a patch is planar.
      size_t bent = 0;
      for (size_t i = 0; i < indices.size(); i += 4) {
        const uint32_t a = uint32_t(indices[i]), b = uint32_t(indices[i + 1]),
                       c = uint32_t(indices[i + 2]), d = uint32_t(indices[i + 3]);
        mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        const Vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a],
                                  mesh.positions[c] - mesh.positions[a]);
        const Vec3 off = mesh.positions[d] - mesh.positions[a];
        const float scale = glm::length(mesh.positions[d] - mesh.positions[a]) * glm::length(n);
        if (std::abs(glm::dot(n, off)) > 1e-5f * scale) ++bent;
      }
      if (bent > 0)
        warn(at,
             fmt::format("{}: {} of {} patches are not planar; each is rendered as two "
                         "triangles",
                         what, bent, indices.size() / 4),
             Divergence::Kind::Approximated);
    }
  } else if (type == "plymesh") {
    const std::string file_name = params.get_string("filename", "");
    if (file_name.empty()) fail(at, what + " needs 'string filename'");
    const std::string file = resolve(at, file_name);
    MeshInFileSpace ply = read_ply_file(file);
    for (const std::string& w : ply.warnings) warn(at, w);
    mesh = std::move(ply.mesh);
    // pbrt makes bilinear patches of a PLY file's quads; emlt splits them into triangles.
    note(at, what +
                 ": quads, if any, are split into two triangles (pbrt makes bilinear "
                 "patches of them: the same surface where they are planar)");
    mesh.colors.clear();
  } else if (type == "disk") {
    const float height = params.get_float("height", 0.0f),
                radius = params.get_float("radius", 1.0f);
    if (!(radius > 0.0f)) Params::fail(*params.get("radius"), "must be positive");
    if (params.get_float("innerradius", 0.0f) > 0.0f || params.get_float("phimax", 360.0f) < 360.0f)
      warn(at, what +
                   ": a partial disk (innerradius, phimax) is not supported; the whole disk "
                   "is used");
    mesh = make_disk_mesh(glm::translate(Mat4(1.0f), Vec3(0.0f, 0.0f, height)) *
                          glm::scale(Mat4(1.0f), Vec3(radius, radius, 1.0f)));
    warn(at, what + " tessellated into 64 triangles (of the disk's area)",
         Divergence::Kind::Approximated);
  } else if (type == "cylinder") {
    const float radius = params.get_float("radius", 1.0f), zmin = params.get_float("zmin", -1.0f),
                zmax = params.get_float("zmax", 1.0f);
    if (!(radius > 0.0f)) Params::fail(*params.get("radius"), "must be positive");
    if (!(zmax != zmin)) fail(at, what + ": zmin and zmax must differ");
    if (params.get_float("phimax", 360.0f) < 360.0f)
      warn(at, what + ": a partial cylinder (phimax) is not supported; the whole cylinder is used");
    mesh = make_cylinder_mesh(Vec3(0.0f, 0.0f, std::min(zmin, zmax)),
                              Vec3(0.0f, 0.0f, std::max(zmin, zmax)), radius, Mat4(1.0f));
    warn(at, what + " tessellated into triangles (of the cylinder's area)",
         Divergence::Kind::Approximated);
  } else if (type == "loopsubdiv" || type == "curve" || type == "cone" || type == "paraboloid" ||
             type == "hyperboloid" || type == "nurbs") {
    for (const Param* p : params.unused()) p->used = true;
    warn(at, what + " is not supported; skipped");
    desc_.skipped_shapes.push_back(what + " at line " + std::to_string(at.line));
    return;
  } else {
    fail(at, "unknown shape type '" + type + "'");
  }
  transform_mesh(mesh, ctm, true);
  if (state_.reverse_orientation) flip_mesh_normals(mesh);
  mesh.name = name;
  mesh.material = material;
  mesh.emission = emission;
  loader::drop_non_finite_triangles(desc_, mesh, at.file);
  report_unused(params, what);
  (current_object_ ? current_object_->meshes : desc_.meshes).push_back(std::move(mesh));
}

}  // namespace emlt::pbrt
