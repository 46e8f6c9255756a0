// pbrt-v4 scene files: directives, the transformation matrix, attributes, includes, named
// materials and object instancing. pbrt-v4 is left-handed with the camera looking down +z;
// its matrices are plain numbers, so only the camera needs converting (pbrt_camera.cpp).
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "emlt/core/error.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/shape_builders.h"
#include "src/scene/loaders/gzip_bytes.h"
#include "src/scene/loaders/loader_common.h"
#include "src/scene/loaders/pbrt_reader.h"

namespace emlt {

namespace pbrt {

namespace {

// Include depth beyond which a file is taken to include itself.
constexpr int kMaxIncludeDepth = 32;

// pbrt's LookAt: the world-to-camera matrix of a camera at `eye` looking at `target`, with
// camera +x = normalize(up x dir) (the image's right in pbrt's left-handed frame).
Mat4 pbrt_look_at(const Vec3& eye, const Vec3& target, const Vec3& up, bool* ok) {
  const Vec3 dir = target - eye;
  *ok = glm::length(dir) > 0.0f && glm::length(up) > 0.0f;
  if (!*ok) return Mat4(1.0f);
  const Vec3 d = glm::normalize(dir);
  const Vec3 r = glm::cross(glm::normalize(up), d);
  *ok = glm::length(r) > 1e-6f;
  if (!*ok) return Mat4(1.0f);
  const Vec3 right = glm::normalize(r);
  const Vec3 new_up = glm::cross(d, right);
  Mat4 camera_to_world(1.0f);
  camera_to_world[0] = Vec4(right, 0.0f);
  camera_to_world[1] = Vec4(new_up, 0.0f);
  camera_to_world[2] = Vec4(d, 0.0f);
  camera_to_world[3] = Vec4(eye, 1.0f);
  return glm::inverse(camera_to_world);
}

}  // namespace

Reader::Reader(const std::string& path) {
  desc_.source = path;
  // pbrt-v4's BSDFs are evaluated in the shading frame alone, with no check of the
  // geometric normal's side: no strict normals.
  desc_.strict_normals = false;
  // pbrt's default integrator (volpath) stops after 5 bounces: emlt's depth counts edges,
  // so 6 (a light seen directly is depth 1 in emlt, 0 in pbrt).
  desc_.render.set("--max-depth", "6");
  // pbrt's default film is 1280 x 720 with a Gaussian filter (pbrt_camera.cpp).
  desc_.camera.width = 1280;
  desc_.camera.height = 720;
  desc_.camera.fov_degrees = 90.0f;
  desc_.camera.fov_axis = CameraDesc::FovAxis::Smaller;
  desc_.camera.to_world = glm::scale(Mat4(1.0f), Vec3(-1.0f, 1.0f, 1.0f));
  desc_.camera.filter.kind = PixelFilterDesc::Kind::Gaussian;
  desc_.camera.filter.stddev = 0.5f;
}

void Reader::fail(const Where& at, const std::string& problem) const {
  throw file_error(at.file, "line " + std::to_string(at.line) + ": " + problem);
}

void Reader::warn(const Where& at, const std::string& message, Divergence::Kind kind) {
  desc_.warnings.push_back(at.file + ": line " + std::to_string(at.line) + ": " + message);
  desc_.divergences.push_back({kind, desc_.warnings.back()});
}

void Reader::note(const Where& at, const std::string& message) {
  desc_.warnings.push_back(at.file + ": line " + std::to_string(at.line) + ": " + message);
}

void Reader::report_unused(const Params& params, const std::string& what) {
  for (const Param* p : params.unused())
    warn({p->file, p->line},
         "parameter " + p->quoted() + " of " + what + " is not supported; ignored");
}

std::string Reader::resolve(const Where& at, const std::string& name) const {
  const std::filesystem::path p(name);
  std::error_code ec;
  const auto beside = std::filesystem::path(at.file).parent_path() / p;
  const bool from_top =
      p.is_absolute() ||
      std::filesystem::is_regular_file(std::filesystem::path(desc_.source).parent_path() / p, ec) ||
      !std::filesystem::is_regular_file(beside, ec);
  return loader::resolve_path(from_top ? desc_.source : at.file, name);
}

int Reader::default_material() {
  if (default_material_ < 0)
    default_material_ = loader::material_index(desc_, make_two_sided(make_lambertian(Rgb(0.5f))),
                                               "pbrt default (diffuse 0.5)");
  return default_material_;
}

SceneDescription Reader::read() {
  read_file(desc_.source, 0);
  if (current_object_)
    fail(current_object_at_, "ObjectBegin \"" + current_object_name_ + "\" without ObjectEnd");
  if (!pending_materials_.empty()) {
    const auto& [material_name, pending] = *pending_materials_.begin();
    fail(pending.first_use, "NamedMaterial \"" + material_name + "\" is not defined");
  }
  if (!stack_.empty())
    note(opened_.back(), std::to_string(stack_.size()) +
                             " AttributeBegin (or TransformBegin) without an end at the end of "
                             "the file (the innermost begins here)");
  if (!in_world_) throw file_error(desc_.source, "no WorldBegin: the file describes no scene");
  CameraDesc& cam = desc_.camera;
  // pbrt's orthographic window is [-1, 1] on the shorter side, emlt's on x.
  if (ortho_ && cam.width > cam.height) {
    const float aspect = float(cam.width) / float(cam.height);
    cam.to_world = cam.to_world * glm::scale(Mat4(1.0f), Vec3(aspect, aspect, 1.0f));
  }
  return std::move(desc_);
}

void Reader::read_file(const std::string& path, int depth) {
  if (depth > kMaxIncludeDepth)
    throw file_error(path, "Include nested more than " + std::to_string(kMaxIncludeDepth) +
                               " deep (does a file include itself?)");
  // pbrt-v4 reads gzip-compressed scene texts (the public hair scenes' curves are).
  Tokenizer tokens(path, loader::maybe_gunzip(path, loader::read_text_file(path)));
  while (std::optional<Token> word = tokens.next()) directive(tokens, *word, depth);
}

void Reader::directive(Tokenizer& tokens, const Token& word, int depth) {
  const Where at{tokens.path(), word.line};
  if (word.kind != Token::Kind::Word)
    fail(at,
         "expected a directive, got " +
             (word.kind == Token::Kind::String ? "\"" + word.text + "\"" : "'" + word.text + "'"));
  const std::string& name = word.text;

  // Positional arguments.
  auto number = [&]() {
    std::optional<Token> t = tokens.next();
    if (!t || t->kind != Token::Kind::Word) fail(at, name + ": expected a number");
    const char* begin = t->text.c_str();
    char* end = nullptr;
    const float v = std::strtof(begin, &end);
    if (end != begin + t->text.size() || !std::isfinite(v))
      fail({at.file, t->line}, name + ": '" + t->text + "' is not a finite number");
    return v;
  };
  auto string = [&]() {
    std::optional<Token> t = tokens.next();
    if (!t || t->kind != Token::Kind::String) fail(at, name + ": expected a quoted string");
    return t->text;
  };
  auto matrix = [&]() {
    std::optional<Token> open = tokens.next();
    const bool bracketed = open && open->kind == Token::Kind::Open;
    if (!bracketed && open) tokens.unget(std::move(*open));
    float values[16];
    for (float& v : values) v = number();
    if (bracketed) {
      std::optional<Token> close = tokens.next();
      if (!close || close->kind != Token::Kind::Close)
        fail(at, name + ": expected ']' after 16 numbers");
    }
    // pbrt reads the 16 numbers row by row and transposes them: they are the matrix column
    // by column, the translation 13th to 15th, which is glm's column-major layout.
    return glm::make_mat4(values);
  };
  auto params = [&]() {
    Params p = Params::read(tokens);
    for (const std::string& replaced : p.replaced())
      note(at,
           name + ": parameter " + replaced + " given again; the last one counts (as in pbrt-v4)");
    return p;
  };
  auto world_only = [&](bool inside) {
    if (inside && !in_world_) fail(at, name + " before WorldBegin");
    if (!inside && in_world_) fail(at, name + " after WorldBegin");
  };

  GraphicsState& g = state_;
  if (name == "Identity") {
    g.ctm = Mat4(1.0f);
  } else if (name == "Translate") {
    const float x = number(), y = number(), z = number();
    g.ctm = g.ctm * glm::translate(Mat4(1.0f), Vec3(x, y, z));
  } else if (name == "Scale") {
    const float x = number(), y = number(), z = number();
    g.ctm = g.ctm * glm::scale(Mat4(1.0f), Vec3(x, y, z));
  } else if (name == "Rotate") {
    const float angle = number(), x = number(), y = number(), z = number();
    const Mat4 r = loader::rotation_matrix(Vec3(x, y, z), angle);
    if (!is_finite_matrix(r)) fail(at, "Rotate about a zero axis");
    g.ctm = g.ctm * r;
  } else if (name == "LookAt") {
    Vec3 v[3];
    for (Vec3& p : v) {
      const float x = number(), y = number(), z = number();
      p = Vec3(x, y, z);
    }
    bool ok = false;
    const Mat4 m = pbrt_look_at(v[0], v[1], v[2], &ok);
    if (!ok)
      fail(at, "LookAt: the eye equals the target, or the up vector is zero or along the view");
    g.ctm = g.ctm * m;
  } else if (name == "Transform") {
    g.ctm = matrix();
  } else if (name == "ConcatTransform") {
    g.ctm = g.ctm * matrix();
  } else if (name == "CoordinateSystem") {
    coordinate_systems_[string()] = g.ctm;
  } else if (name == "CoordSysTransform") {
    const std::string system = string();
    const auto it = coordinate_systems_.find(system);
    if (it == coordinate_systems_.end())
      warn(at, "CoordSysTransform: no coordinate system named '" + system + "'; ignored");
    else
      g.ctm = it->second;
  } else if (name == "ReverseOrientation") {
    g.reverse_orientation = !g.reverse_orientation;
  } else if (name == "TransformTimes") {
    const float start = number(), end = number();
    (void)start, (void)end;
    note(at, "TransformTimes: emlt renders no motion blur; the shutter is not used");
  } else if (name == "ActiveTransform") {
    std::optional<Token> t = tokens.next();
    if (!t || t->kind != Token::Kind::Word ||
        (t->text != "All" && t->text != "StartTime" && t->text != "EndTime"))
      fail(at, "ActiveTransform: expected All, StartTime or EndTime");
    if (t->text != "All")
      warn(at, "ActiveTransform " + t->text +
                   ": animated transforms are not supported; every "
                   "transform applies at all times");
  } else if (name == "AttributeBegin" || name == "TransformBegin") {
    stack_.push_back({g, name == "AttributeBegin" ? 'a' : 't'});
    opened_.push_back(at);
  } else if (name == "AttributeEnd" || name == "TransformEnd") {
    const char kind = name == "AttributeEnd" ? 'a' : 't';
    if (stack_.empty() || stack_.back().second != kind)
      fail(at, name + " without a matching " + (kind == 'a' ? "AttributeBegin" : "TransformBegin"));
    if (kind == 'a')
      g = stack_.back().first;
    else
      g.ctm = stack_.back().first.ctm;
    stack_.pop_back();
    opened_.pop_back();
  } else if (name == "Attribute") {
    const std::string target = string();
    const Params p = params();
    for (const Param* param : p.unused())
      warn({param->file, param->line},
           "Attribute \"" + target + "\" " + param->quoted() +
               ": default parameters for later directives are not supported; ignored");
  } else if (name == "Option") {
    const Params p = params();
    for (const Param* param : p.unused())
      note({param->file, param->line}, "Option " + param->quoted() + " ignored");
  } else if (name == "ColorSpace") {
    const std::string space = string();
    if (space != "srgb")
      warn(at,
           "ColorSpace \"" + space + "\": emlt renders in linear sRGB; colours are read as sRGB");
  } else if (name == "Camera") {
    world_only(false);
    const std::string type = string();
    camera(at, type, params());
    coordinate_systems_["camera"] = glm::inverse(g.ctm);
  } else if (name == "Film") {
    world_only(false);
    const std::string type = string();
    film(at, type, params());
  } else if (name == "Sampler") {
    world_only(false);
    const std::string type = string();
    sampler(at, type, params());
  } else if (name == "Integrator") {
    world_only(false);
    const std::string type = string();
    integrator(at, type, params());
  } else if (name == "PixelFilter") {
    world_only(false);
    const std::string type = string();
    pixel_filter(at, type, params());
  } else if (name == "Accelerator") {
    const std::string type = string();
    const Params p = params();
    for (const Param* param : p.unused()) param->used = true;
    note(at, "Accelerator \"" + type + "\" ignored (emlt builds its own; the image is the same)");
  } else if (name == "WorldBegin") {
    world_only(false);
    in_world_ = true;
    if (!filter_seen_) {
      const Params none;
      pixel_filter(at, "gaussian", none);
      filter_seen_ = false;
    }
    // pbrt resets the matrix and names the world's frame.
    g.ctm = Mat4(1.0f);
    coordinate_systems_["world"] = g.ctm;
  } else if (name == "WorldEnd") {
    note(at, "WorldEnd (pbrt-v3) ignored");
  } else if (name == "MakeNamedMedium") {
    const std::string medium = string();
    const Params p = params();
    for (const Param* param : p.unused()) param->used = true;
    warn(at, "MakeNamedMedium \"" + medium + "\": participating media are not supported; ignored");
  } else if (name == "MediumInterface") {
    const std::string inside = string();
    std::string outside = inside;
    if (std::optional<Token> t = tokens.next()) {
      if (t->kind == Token::Kind::String)
        outside = t->text;
      else
        tokens.unget(std::move(*t));
    }
    if (!inside.empty() || !outside.empty())
      warn(at, "MediumInterface \"" + inside + "\" \"" + outside +
                   "\": participating media are not supported; every medium is a vacuum");
  } else if (name == "Shape") {
    world_only(true);
    const std::string type = string();
    shape(at, type, params());
  } else if (name == "LightSource") {
    world_only(true);
    const std::string type = string();
    light(at, type, params());
  } else if (name == "AreaLightSource") {
    world_only(true);
    const std::string type = string();
    area_light(at, type, params());
  } else if (name == "Material") {
    world_only(true);
    const std::string type = string();
    bool interface = false;
    const Params p = params();
    g.material = material(
        at, type, p, "Material \"" + type + "\" at line " + std::to_string(at.line), &interface);
    g.interface = interface;
  } else if (name == "MakeNamedMaterial") {
    world_only(true);
    const std::string material_name = string();
    const Params p = params();
    if (!p.has("type"))
      fail(at, "MakeNamedMaterial \"" + material_name + "\" needs a 'string type'");
    const std::string type = p.get_string("type", "");
    bool interface = false;
    const int index = material(at, type, p, material_name, &interface);
    named_materials_[material_name] = index;
    named_interfaces_[material_name] = interface;
    if (const auto pending = pending_materials_.find(material_name);
        pending != pending_materials_.end()) {
      if (interface)
        fail(at, "MakeNamedMaterial \"" + material_name + "\" is an interface, but line " +
                     std::to_string(pending->second.first_use.line) + " of " +
                     pending->second.first_use.file +
                     " used it before, as a surface (declare an interface before its use)");
      const MaterialDesc& defined = desc_.materials[size_t(index)];
      for (MaterialDesc& m : desc_.materials)
        if (m.bsdf == pending->second.stand_in) {
          m.bsdf = defined.bsdf;
          m.textured = m.textured || defined.textured;
        }
      pending_materials_.erase(pending);
    }
  } else if (name == "NamedMaterial") {
    world_only(true);
    const std::string material_name = string();
    g.interface = false;
    if (const auto it = named_materials_.find(material_name); it != named_materials_.end()) {
      g.material = it->second;
      g.interface = named_interfaces_[material_name];
    } else if (const auto pending = pending_materials_.find(material_name);
               pending != pending_materials_.end()) {
      g.material = pending->second.index;
    } else {
      BsdfPtr stand_in = make_two_sided(make_lambertian(Rgb(0.5f)));
      desc_.materials.push_back(MaterialDesc(material_name, stand_in));
      g.material = int(desc_.materials.size()) - 1;
      pending_materials_[material_name] = {g.material, stand_in, at};
    }
  } else if (name == "Texture") {
    world_only(true);
    const std::string texture_name = string(), kind = string(), type = string();
    texture_declaration(at, texture_name, kind, type, params());
  } else if (name == "ObjectBegin") {
    world_only(true);
    const std::string object = string();
    if (current_object_) fail(at, "ObjectBegin \"" + object + "\" inside another ObjectBegin");
    if (objects_.count(object)) fail(at, "object \"" + object + "\" defined twice");
    stack_.push_back({g, 'a'});
    opened_.push_back(at);
    current_object_at_ = at;
    current_object_ = &objects_[object];
    current_object_name_ = object;
  } else if (name == "ObjectEnd") {
    if (!current_object_) fail(at, "ObjectEnd without ObjectBegin");
    if (stack_.empty() || stack_.back().second != 'a')
      fail(at, "ObjectEnd inside an unclosed TransformBegin");
    g = stack_.back().first;
    stack_.pop_back();
    opened_.pop_back();
    current_object_ = nullptr;
  } else if (name == "ObjectInstance") {
    world_only(true);
    const std::string object = string();
    if (current_object_) fail(at, "ObjectInstance inside ObjectBegin (nested instancing)");
    const auto it = objects_.find(object);
    if (it == objects_.end()) fail(at, "ObjectInstance \"" + object + "\" is not defined");
    if (!is_finite_matrix(g.ctm))
      fail(at, "ObjectInstance: the transformation has NaN or infinity");
    // Instances are copied into the scene: the same image, more memory.
    for (MeshDesc mesh : it->second.meshes) {
      transform_mesh(mesh, g.ctm, true);
      mesh.name += " (instance at line " + std::to_string(at.line) + ")";
      loader::drop_non_finite_triangles(desc_, mesh, at.file);
      desc_.meshes.push_back(std::move(mesh));
    }
    for (SphereDesc sphere : it->second.spheres) {
      place_sphere(at, sphere, g.ctm);
      desc_.spheres.push_back(sphere);
    }
  } else if (name == "Include" || name == "Import") {
    const std::string file = string();
    const std::string resolved = resolve(at, file);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(resolved, ec))
      fail(at, name + " \"" + file + "\": file not found");
    read_file(resolved, depth + 1);
  } else {
    fail(at, "unknown directive '" + name + "'");
  }
}

}  // namespace pbrt

SceneDescription load_pbrt_scene(const std::string& path) {
  return pbrt::Reader(path).read();
}

}  // namespace emlt
