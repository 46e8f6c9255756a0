// Mitsuba 0.6 XML scenes: the subset that maps onto this renderer (see scenes/README.md).
// Everything else is reported as a warning naming the element and its line. This file reads
// the document, its shapes and its environment; the sensor, BSDFs, textures, delta lights,
// daylight and the render request have readers of their own beside it (mitsuba_*.cpp).
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <string_view>

#include "emlt/core/error.h"
#include "emlt/image/image.h"
#include "emlt/scene/loaders/load_prefetch.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/loaders/obj_loader.h"
#include "emlt/scene/loaders/ply_loader.h"
#include "emlt/scene/loaders/serialized_loader.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/shape_builders.h"
#include "emlt/settings/settings.h"
#include "src/scene/loaders/loader_common.h"
#include "src/scene/loaders/mitsuba_parser.h"
#include "src/scene/loaders/mitsuba_sensor.h"
#include "src/scene/loaders/mitsuba_sky.h"

namespace emlt {

namespace {

using mitsuba::Document;
using mitsuba::Properties;

// The shapes a <shape type="shapegroup"> declares, in the group's own space.
struct ShapeGroup {
  std::vector<MeshDesc> meshes;
  std::vector<SphereDesc> spheres;
};

class MitsubaSceneReader {
 public:
  MitsubaSceneReader(const std::string& path, const SceneDefines& defines)
      : doc_(path, defines, desc_.warnings, desc_.divergences) {
    desc_.source = path;
    // Without an <integrator> Mitsuba renders with its path tracer, whose strictNormals is
    // false by default.
    desc_.strict_normals = false;
  }

  SceneDescription read() {
    const pugi::xml_node scene = doc_.scene();
    for (pugi::xml_node child : scene.children("default"))
      doc_.add_default(child.attribute("name").as_string(), child.attribute("value").as_string());
    const LoadPrefetch prefetch = announce_files(scene);
    // Textures, then BSDFs, first so a <ref> may precede the declaration it names.
    for (pugi::xml_node child : scene.children("texture"))
      mitsuba::read_texture(doc_, child, named_);
    for (pugi::xml_node child : scene.children("bsdf"))
      mitsuba::read_bsdf(doc_, child, named_, desc_.warnings);
    // Shape groups too, for the instances that refer to them.
    for (pugi::xml_node child : scene.children("shape"))
      if (doc_.attribute(child, "type") == "shapegroup") read_shape_group(child);
    bool has_sensor = false;
    for (pugi::xml_node child : scene.children()) {
      if (child.type() != pugi::node_element) continue;
      const std::string kind = child.name();
      if (kind == "default" || kind == "bsdf" || kind == "texture") continue;
      if (kind == "shape")
        read_shape(child);
      else if (kind == "emitter") {
        if (!mitsuba::read_delta_light(doc_, child, named_, desc_)) read_environment(child);
      }
      else if (kind == "sensor") {
        if (has_sensor)
          doc_.warn(child, "only the first <sensor> is used");
        else
          mitsuba::read_sensor(doc_, child, desc_);
        has_sensor = true;
      } else if (kind == "integrator")
        desc_.strict_normals = mitsuba::read_integrator(doc_, child, desc_.render);
      else if (kind == "medium" && !referenced(doc_.attribute(child, "id")))
        // A medium only acts where a shape or sensor names it; exporters leave unused ones.
        doc_.warn(child,
                  "<medium> '" + doc_.attribute(child, "id") + "' is used by nothing; ignored",
                  Document::Warning::Note);
      else
        doc_.warn(child, "unsupported element <" + kind + "> ignored");
    }
    if (!has_sensor)
      desc_.warnings.push_back(doc_.path() + ": no <sensor>; using the default camera");
    return std::move(desc_);
  }

  // The meshes and images the document names, read ahead (load_prefetch.h). Only what the
  // file states plainly is announced (no `$name` in a file name, literal booleans); the
  // rest, and anything this guesses wrong, is read where the loader meets it.
  LoadPrefetch announce_files(pugi::xml_node scene) const {
    std::vector<std::string> images;
    std::vector<LoadPrefetch::Obj> objs;
    std::vector<LoadPrefetch::MeshFile> meshes;
    const auto value_of = [](pugi::xml_node node, const char* tag, const char* name) {
      for (pugi::xml_node child : node.children(tag))
        if (std::string_view(child.attribute("name").as_string()) == name)
          return std::optional<std::string>(child.attribute("value").as_string());
      return std::optional<std::string>();
    };
    const auto plain_file = [&](pugi::xml_node node) -> std::optional<std::string> {
      const auto file = value_of(node, "string", "filename");
      if (!file || file->empty() || file->find('$') != std::string::npos) return std::nullopt;
      return loader::resolve_path(doc_.path(), *file);
    };
    const auto flag = [&](pugi::xml_node node, const char* name,
                          bool fallback) -> std::optional<bool> {
      const auto text = value_of(node, "boolean", name);
      if (!text) return fallback;
      if (*text == "true" || *text == "false") return *text == "true";
      return std::nullopt;
    };
    const pugi::xpath_node_set named = scene.select_nodes(
        "//texture[@type='bitmap'] | //shape[@type='obj'] | //shape[@type='ply'] | "
        "//shape[@type='serialized']");
    for (const pugi::xpath_node& found : named) {
      const pugi::xml_node node = found.node();
      const auto file = plain_file(node);
      if (!file) continue;
      // Regular files only, as the loader reads: a FIFO or a device named as a texture would
      // block a task (and the loader's end, which waits for the tasks) for ever.
      std::error_code ec;
      if (!std::filesystem::is_regular_file(*file, ec)) continue;
      if (std::string_view(node.name()) == "texture") {
        if (is_stored_image(*file)) images.push_back(*file);
        continue;
      }
      const std::string_view type = node.attribute("type").as_string();
      if (type == "ply") {
        meshes.push_back({LoadPrefetch::MeshFile::Format::Ply, *file, 0});
        continue;
      }
      if (type == "serialized") {
        const std::string index = value_of(node, "integer", "shapeIndex").value_or("0");
        int shape_index = -1;
        const auto [end, ec] =
            std::from_chars(index.data(), index.data() + index.size(), shape_index);
        if (ec == std::errc() && end == index.data() + index.size() && shape_index >= 0)
          meshes.push_back({LoadPrefetch::MeshFile::Format::Serialized, *file, shape_index});
        continue;
      }
      const auto face_normals = flag(node, "faceNormals", false),
                 flip = flag(node, "flipTexCoords", true), collapse = flag(node, "collapse", false);
      if (face_normals && flip && collapse && !*collapse)
        objs.push_back({*file, !*face_normals, *flip});
    }
    return LoadPrefetch(images, objs, meshes);
  }

 private:
  // Whether any <ref> of the document names `id` ("" never is).
  bool referenced(const std::string& id) const {
    if (id.empty()) return true;  // cannot tell; treat as used
    for (pugi::xpath_node ref : doc_.scene().select_nodes("//ref"))
      if (doc_.attribute(ref.node(), "id") == id) return true;
    return false;
  }

  // Mitsuba's BSDF for a shape that names none: a one-sided diffuse of reflectance 0.5,
  // or, on an emitter, a black one (a lamp reflects nothing).
  int default_material(bool emitter) {
    int& index = emitter ? default_emitter_material_ : default_material_;
    if (index < 0)
      index = loader::material_index(
          desc_, make_lambertian(Rgb(emitter ? 0.0f : 0.5f)),
          emitter ? "default (black diffuse, emitter)" : "default (diffuse 0.5)");
    return index;
  }

  int material_of(pugi::xml_node node) {
    MaterialDesc material = mitsuba::read_bsdf(doc_, node, named_, desc_.warnings);
    if (material.name.empty())
      material.name = doc_.has_attribute(node, "id")
                          ? doc_.attribute(node, "id")
                          : "bsdf at line " + std::to_string(doc_.line(node));
    return loader::material_index(desc_, material);
  }

  // <shape type="shapegroup" id=...>: its shapes, kept for the instances that refer to it
  // (a group renders nothing by itself).
  void read_shape_group(pugi::xml_node node) {
    if (!doc_.has_attribute(node, "id")) {
      doc_.warn(node, "shapegroup without an id cannot be instanced; skipped");
      return;
    }
    const std::string id = doc_.attribute(node, "id");
    ShapeGroup& group = groups_[id];
    group = {};
    Properties props(doc_, node);
    for (pugi::xml_node child : props.objects()) {
      if (std::string(child.name()) == "shape")
        read_shape(child, &group);
      else
        doc_.warn(child, "unsupported element " + doc_.describe(child) +
                             " inside <shape type=\"shapegroup\"> ignored");
    }
    props.warn_unused();
  }

  // <shape type="instance">: the referenced group's shapes, copied into world space.
  void read_instance(pugi::xml_node node, Properties& props) {
    const Mat4 to_world = props.get_transform("toWorld");
    const ShapeGroup* group = nullptr;
    for (pugi::xml_node child : props.objects()) {
      const std::string kind = child.name();
      if (kind == "ref" && !group) {
        const std::string id = doc_.attribute(child, "id");
        const auto it = groups_.find(id);
        if (it == groups_.end())
          doc_.fail(child, "instance refers to '" + id + "', which is not a shapegroup");
        group = &it->second;
      } else {
        doc_.warn(child, "unsupported element " + doc_.describe(child) +
                             " inside <shape type=\"instance\"> ignored (the group's shapes "
                             "keep their own)");
      }
    }
    if (!group) doc_.fail(node, "instance needs a <ref id=...> naming a shapegroup");
    if (!is_finite_matrix(to_world)) doc_.fail(node, "instance toWorld contains NaN or infinity");
    props.warn_unused();
    const std::string suffix = " (instance at line " + std::to_string(doc_.line(node)) + ")";
    for (MeshDesc mesh : group->meshes) {
      // Mitsuba transforms an instance's normals by the inverse transpose, so the
      // facing survives a mirroring transform.
      transform_mesh(mesh, to_world, true);
      mesh.name += suffix;
      desc_.meshes.push_back(std::move(mesh));
    }
    for (SphereDesc sphere : group->spheres) {
      loader::transform_sphere(sphere, to_world, doc_.path() + ": " + sphere.name + suffix,
                               desc_.warnings);
      sphere.name += suffix;
      desc_.spheres.push_back(sphere);
    }
  }

  // A shape for the scene, or for `group` when it is declared inside a shapegroup.
  void read_shape(pugi::xml_node node, ShapeGroup* group = nullptr) {
    const std::string type = doc_.attribute(node, "type");
    if (type == "shapegroup" || type == "instance") {
      if (group) doc_.fail(node, "nested instancing is not supported (nor by Mitsuba)");
      if (type == "shapegroup") return;  // read before the other shapes
      Properties props(doc_, node);
      read_instance(node, props);
      return;
    }
    static const char* kSupported[] = {"obj",    "rectangle",  "cube",     "disk",
                                       "sphere", "serialized", "cylinder", "ply"};
    if (std::find_if(std::begin(kSupported), std::end(kSupported),
                     [&](const char* t) { return type == t; }) == std::end(kSupported)) {
      doc_.warn(node, "unsupported shape type '" + type + "' " + doc_.describe(node) + " skipped");
      desc_.skipped_shapes.push_back(doc_.describe(node) + " at line " +
                                     std::to_string(doc_.line(node)));
      return;
    }
    Properties props(doc_, node);
    const std::string name = type + " at line " + std::to_string(doc_.line(node));
    const Mat4 to_world = props.get_transform("toWorld");
    int material = -1;
    Rgb emission(0.0f);
    // <ref name="bsdf" id=...>: a named reference is a parameter, not an object.
    for (const std::string& ref : props.names_of_kind("ref")) {
      props.ignore({ref.c_str()});
      for (pugi::xml_node child : node.children("ref")) {
        if (child.attribute("name").as_string() != ref) continue;
        if (ref == "interior" || ref == "exterior")
          doc_.warn(child, "participating medium '" + doc_.attribute(child, "id") + "' (" + ref +
                               ") is not supported; the shape's inside is a vacuum");
        else
          material = material_of(child);
      }
    }
    for (pugi::xml_node child : props.objects()) {
      const std::string kind = child.name();
      if (kind == "bsdf" || kind == "ref") {
        if (material >= 0) doc_.warn(child, "shape has several BSDFs; the last one is used");
        material = material_of(child);
      } else if (kind == "emitter" && doc_.attribute(child, "type") == "area") {
        if (group)
          doc_.fail(child, "an emitter inside a shapegroup is not supported (nor by Mitsuba)");
        Properties emitter(doc_, child);
        // The shape places an area light: Mitsuba refuses a transform of its own.
        if (emitter.has("toWorld"))
          doc_.fail(emitter.node_of("toWorld"),
                    "an area emitter takes no 'toWorld' (Mitsuba refuses it: the shape's "
                    "transform places the light)");
        emission = emitter.get_color("radiance", Rgb(1.0f));
        emitter.note_sampling_only({"samplingWeight"}, "how often Mitsuba samples this light");
        emitter.warn_unused();
      } else {
        doc_.warn(child, "unsupported element " + doc_.describe(child) + " inside <shape> ignored");
      }
    }
    if (material < 0) material = default_material(!is_black(emission));
    const bool flip = props.get_boolean("flipNormals", false);

    if (type == "sphere") {
      SphereDesc sphere;
      sphere.name = name;
      sphere.center = props.get_point("center", Vec3(0.0f));
      sphere.radius = props.get_float("radius", 1.0f, loader::kPositiveRange);
      loader::transform_sphere(sphere, to_world, doc_.path() + ": " + name, desc_.warnings);
      sphere.material = material;
      sphere.emission = emission;
      sphere.flip_normals = flip;
      props.warn_unused();
      (group ? group->spheres : desc_.spheres).push_back(sphere);
      return;
    }
    MeshDesc mesh;
    if (type == "obj") {
      if (!props.has("filename")) doc_.fail(node, "<shape type=\"obj\"> needs a 'filename'");
      const std::string file = loader::resolve_path(doc_.path(), props.get_string("filename", ""));
      // Mitsuba uses the file's normals (or computes smooth ones) unless faceNormals is set.
      const bool face_normals = props.get_boolean("faceNormals", false);
      // Mitsuba flips OBJ texture coordinates by default (v = 0 at the image's top).
      const bool flip_uv = props.get_boolean("flipTexCoords", true);
      // Mitsuba makes a mesh of each group (and each material's run of faces) unless
      // collapse merges them; shapeIndex keeps one of them.
      const bool collapse = props.get_boolean("collapse", false);
      const int shape_index = props.get_integer("shapeIndex", -1);
      std::optional<ObjInFileSpace> obj =
          collapse ? std::nullopt : LoadPrefetch::obj(file, !face_normals, flip_uv);
      if (!obj) obj = read_obj_file(file, !face_normals, flip_uv, collapse);
      keep_obj_part(*obj, shape_index);
      if (shape_index >= 0 && obj->mesh.indices.empty()) {
        doc_.warn(node,
                  fmt::format("shapeIndex {} selects none of the meshes Mitsuba makes of {} "
                              "(Mitsuba adds none either)",
                              shape_index, std::filesystem::path(file).filename().string()),
                  Document::Warning::Note);
        props.ignore({"maxSmoothAngle", "loadMaterials"});
        props.warn_unused();
        return;
      }
      obj_materials(node, props, *obj, file);
      mesh = place_obj_mesh(std::move(*obj), to_world, &desc_.warnings);
      loader::drop_non_finite_triangles(desc_, mesh, file);
      if (props.has("maxSmoothAngle")) {
        if (face_normals)
          doc_.fail(node, "'maxSmoothAngle' and 'faceNormals' cannot be given together");
        split_vertices_by_angle(mesh, props.get_float("maxSmoothAngle", 0.0f));
      }
    } else if (type == "rectangle") {
      mesh = make_rectangle_mesh(to_world);
    } else if (type == "serialized") {
      if (!props.has("filename")) doc_.fail(node, "<shape type=\"serialized\"> needs a 'filename'");
      const std::string file = loader::resolve_path(doc_.path(), props.get_string("filename", ""));
      const int index = props.get_integer("shapeIndex", 0, loader::kShapeIndexRange);
      std::optional<MeshInFileSpace> prefetched =
          LoadPrefetch::mesh({LoadPrefetch::MeshFile::Format::Serialized, file, index});
      mesh = prefetched ? place_serialized_mesh(std::move(prefetched->mesh), to_world)
                        : load_serialized_mesh(file, index, to_world);
      loader::drop_non_finite_triangles(desc_, mesh, file);
      read_mesh_normal_options(node, props, mesh, flip);
    } else if (type == "ply") {
      if (!props.has("filename")) doc_.fail(node, "<shape type=\"ply\"> needs a 'filename'");
      const std::string file = loader::resolve_path(doc_.path(), props.get_string("filename", ""));
      std::optional<MeshInFileSpace> prefetched =
          LoadPrefetch::mesh({LoadPrefetch::MeshFile::Format::Ply, file, 0});
      mesh = prefetched ? place_ply_mesh(std::move(*prefetched), to_world, &desc_.warnings)
                        : load_ply_mesh(file, to_world, &desc_.warnings);
      if (props.get_boolean("srgb", true)) decode_srgb_vertex_colors(mesh);
      loader::drop_non_finite_triangles(desc_, mesh, file);
      read_mesh_normal_options(node, props, mesh, flip);
    } else if (type == "cylinder") {
      const Vec3 p0 = props.get_point("p0", Vec3(0.0f));
      const Vec3 p1 = props.get_point("p1", Vec3(0.0f, 0.0f, 1.0f));
      const float radius = props.get_float("radius", 1.0f, loader::kPositiveRange);
      if (!(glm::length(p1 - p0) > 0.0f) || !std::isfinite(glm::length(p1 - p0)))
        doc_.fail(node, "cylinder p0 and p1 must be distinct finite points");
      mesh = make_cylinder_mesh(p0, p1, radius, to_world);
    } else if (type == "cube") {
      // Mitsuba's cube already has one normal per face: faceNormals changes nothing.
      props.get_boolean("faceNormals", false);
      mesh = make_cube_mesh(to_world);
    } else {
      mesh = make_disk_mesh(to_world);
    }
    // The file meshes applied flipNormals with their normal options above.
    if (flip && type != "serialized" && type != "ply") flip_mesh_normals(mesh);
    const bool from_file = type == "obj" || type == "serialized" || type == "ply";
    mesh.name = from_file ? mesh.name + " (line " + std::to_string(doc_.line(node)) + ")" : name;
    mesh.material = material;
    mesh.emission = emission;
    props.warn_unused();
    if (mesh.indices.empty()) {
      doc_.warn(node, "shape " + mesh.name + " has no triangles; skipped");
      return;
    }
    (group ? group->meshes : desc_.meshes).push_back(std::move(mesh));
  }

  // Mitsuba's OBJ reader gives each mesh the material its `usemtl` names in the file's
  // material library (loadMaterials, on by default), which a <bsdf> inside the shape
  // replaces for every mesh (or, given a name, for the meshes of that material). emlt reads
  // no material library: where Mitsuba would use one, that is reported.
  void obj_materials(pugi::xml_node node, Properties& props, const ObjInFileSpace& obj,
                     const std::string& file) {
    const bool load_materials = props.get_boolean("loadMaterials", true);
    if (!load_materials || !obj.has_material_library) return;
    bool replaced = false;
    for (pugi::xml_node child : props.objects()) {
      const std::string kind = child.name();
      if ((kind == "bsdf" || kind == "ref") && !child.attribute("name"))
        replaced = true;  // Mitsuba gives an unnamed BSDF to every mesh of the file
    }
    if (!replaced)
      doc_.warn(node, "the materials of " + std::filesystem::path(file).filename().string() +
                          "'s material library (mtllib) are not loaded; its faces get the "
                          "shape's BSDF (Mitsuba uses the library's, loadMaterials)");
  }

  // faceNormals, maxSmoothAngle and flipNormals of a mesh read from a file, as Mitsuba's
  // TriMesh applies them (after the transform).
  void read_mesh_normal_options(pugi::xml_node node, Properties& props, MeshDesc& mesh, bool flip) {
    const bool face_normals = props.get_boolean("faceNormals", false);
    if (props.has("maxSmoothAngle")) {
      if (face_normals)
        doc_.fail(node, "'maxSmoothAngle' and 'faceNormals' cannot be given together");
      split_vertices_by_angle(mesh, props.get_float("maxSmoothAngle", 0.0f));
    }
    apply_mesh_normal_options(mesh, face_normals, flip);
  }

  void read_environment(pugi::xml_node node) {
    const std::string type = doc_.attribute(node, "type");
    if (mitsuba::is_sky_emitter(type))
      return mitsuba::read_sky_emitter(doc_, node, desc_);
    if (type != "envmap" && type != "constant") {
      doc_.warn(node,
                "unsupported emitter type '" + type + "' " + doc_.describe(node) + " ignored");
      return;
    }
    if (desc_.environment.kind != EnvironmentDesc::Kind::None) {
      doc_.warn(node, "only one environment emitter is supported; this one is ignored");
      return;
    }
    Properties props(doc_, node);
    props.ignore({"cache"});
    props.note_sampling_only({"samplingWeight", "mis_compensation"},
                             "how often Mitsuba samples this light");
    EnvironmentDesc& env = desc_.environment;
    if (type == "constant") {
      env.kind = EnvironmentDesc::Kind::Constant;
      env.radiance = props.get_color("radiance", Rgb(1.0f));
      // Every Mitsuba emitter reads a toWorld; turning a uniform sky changes nothing.
      props.get_transform("toWorld");
    } else {
      if (!props.has("filename")) doc_.fail(node, "<emitter type=\"envmap\"> needs a 'filename'");
      env.scale = props.get_float("scale", 1.0f, loader::kNonNegativeRange);
      env.to_world = props.get_transform("toWorld");
      // Mitsuba's `gamma` replaces the map's own curve, as a bitmap texture's does: -1 sRGB,
      // g > 0 the curve v^g, 0 (the default) the file's.
      std::optional<float> gamma;
      if (const float value = props.get_float("gamma", 0.0f); value == kSrgbGamma || value > 0.0f)
        gamma = value;
      else if (value != 0.0f)
        doc_.fail(props.node_of("gamma"),
                  fmt::format("envmap gamma {} is not a curve (expected -1 for sRGB or a "
                              "positive exponent)",
                              value));
      loader::load_environment_map(
          env, doc_.path(), loader::resolve_path(doc_.path(), props.get_string("filename", "")),
          gamma);
    }
    for (pugi::xml_node child : props.objects())
      doc_.warn(child, "unsupported element " + doc_.describe(child) + " inside <emitter> ignored");
    props.warn_unused();
  }

  SceneDescription desc_;  // before doc_, which appends to its warnings
  Document doc_;
  mitsuba::NamedObjects named_;
  std::map<std::string, ShapeGroup> groups_;  // shapegroups by id
  int default_material_ = -1, default_emitter_material_ = -1;
};

}  // namespace

SceneDescription load_mitsuba_scene(const std::string& path, const SceneDefines& defines) {
  return MitsubaSceneReader(path, defines).read();
}

}  // namespace emlt
