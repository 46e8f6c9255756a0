#pragma once
// Plain-data description of a scene, produced by every loader (JSON, Mitsuba XML) and
// consumed by Scene::build. Two loaders agree on a scene exactly when they produce the
// same description, which keeps format-specific code out of the renderer.
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emlt/core/math.h"
#include "emlt/film/pixel_filter.h"
#include "emlt/image/image.h"
#include "emlt/scene/bsdf.h"
#include "emlt/scene/texture.h"

namespace emlt {

struct MeshDesc {
  std::string name;  // origin, for messages ("walls.obj", "rectangle #3")
  std::vector<Vec3> positions;  // world space
  std::vector<Vec3> normals;    // per vertex, world space; empty = flat shading
  std::vector<Vec2> uvs;        // per vertex; may be empty
  // Per vertex, linear RGB (a PLY file's colours, a serialized mesh's); empty = none.
  std::vector<Rgb> colors;
  std::vector<uint32_t> indices;  // 3 per triangle
  int material = -1;              // index into SceneDescription::materials
  Rgb emission{0.0f};             // area-light radiance, emitted on the normal side
};

// A mesh as its file holds it, before the shape's transform places it, with the reader's
// warnings (a PLY file's skipped faces; a serialized mesh has none): what a scene's loader
// reads ahead in parallel (load_prefetch.h).
struct MeshInFileSpace {
  MeshDesc mesh;
  std::vector<std::string> warnings;
};

struct SphereDesc {
  std::string name;
  Vec3 center{0.0f};
  float radius = 1.0f;
  int material = -1;
  Rgb emission{0.0f};
  bool flip_normals = false;
};

// A surface's appearance: the BSDF plus what changes the surface itself rather than how
// it scatters (Mitsuba's `mask` and `bumpmap` wrappers, which the loaders unwrap here).
struct MaterialDesc {
  MaterialDesc() = default;
  // Not an aggregate, so that the common {name, bsdf} form stays free of
  // missing-initialiser warnings.
  MaterialDesc(std::string name_, BsdfPtr bsdf_, TexturePtr opacity_ = nullptr,
               TexturePtr bump_ = nullptr, bool textured_ = false)
      : name(std::move(name_)), bsdf(std::move(bsdf_)), opacity(std::move(opacity_)),
        bump(std::move(bump_)), textured(textured_) {}

  std::string name;
  BsdfPtr bsdf;
  // Opacity in [0, 1] (texture luminance): a hit is kept with this probability, decided
  // by a hash of the ray so renders stay deterministic; null = opaque.
  TexturePtr opacity;
  // Bump height (texture luminance, in world units per unit of uv); perturbs the
  // shading normal at hit time. Null = none.
  TexturePtr bump;
  // Some parameter varies over uv: a mesh without texture coordinates then gets a
  // planar projection (with a warning) instead of per-triangle barycentrics.
  bool textured = false;
  // Some parameter is a `vertexcolors` texture: a surface without per-vertex colours
  // then reads black, with a warning.
  bool reads_vertex_colors = false;
};

struct EnvironmentDesc {
  enum class Kind { None, Constant, Map, CubeMap } kind = Kind::None;
  Rgb radiance{0.0f};      // Constant
  std::string map_path;    // Map: lat-long .exr/.hdr, already resolved to a usable path
  Image map;               // Map: loaded texels
  std::vector<Image> cube_faces;  // CubeMap: +x, -x, +y, -y, +z, -z (cube_map_environment.h)
  float scale = 1.0f;
  Mat4 to_world{1.0f};     // rotation of the map (directions only)
};

// Mitsuba 0.6's point and spot emitters (scene/point_light.h).
struct PointLightDesc {
  Vec3 position{0.0f};
  Mat3 orientation{1.0f};  // columns: the light's x, y and z (the spot's axis), unit length
  Rgb intensity{1.0f};     // W/sr
  bool spot = false;
  float cutoff = 0.0f, beam_width = 0.0f;  // radians (spot)
  TexturePtr texture;                      // spot only; null: white
};

// Mitsuba 0.6's directional emitter (scene/directional_light.h).
struct DirectionalLightDesc {
  Vec3 direction{0.0f, 0.0f, 1.0f};  // the direction the light travels in
  Rgb irradiance{1.0f};              // at normal incidence
};

// Mitsuba 0.6's collimated emitter (scene/collimated_light.h).
struct CollimatedLightDesc {
  Vec3 origin{0.0f};
  Vec3 direction{0.0f, 0.0f, 1.0f};  // the beam's
  Rgb power{1.0f};                   // W
};

struct CameraDesc {
  // Camera space: +z forward, +y up, +x to the image's left (Mitsuba's convention), so a
  // Mitsuba `toWorld` can be used unchanged. JSON `lookat` builds the same matrix.
  Mat4 to_world{1.0f};
  // Orthographic: parallel rays along +z from the camera space square x in [-1, 1],
  // y in [-1/aspect, 1/aspect] (scaled by to_world), as Mitsuba's `orthographic` sensor.
  enum class Projection { Perspective, Orthographic } projection = Projection::Perspective;
  float fov_degrees = 45.0f;
  enum class FovAxis { X, Y, Smaller, Larger } fov_axis = FovAxis::X;
  float aperture_radius = 0.0f;  // 0: pinhole
  float focus_distance = 1.0f;
  int width = 256, height = 256;
  // Mitsuba's crop window, in pixels of the width x height film: only that window is
  // rendered and written (an image of its size), and the whole film still frames the view.
  // A zero size means the whole film.
  int crop_x = 0, crop_y = 0, crop_width = 0, crop_height = 0;
  bool cropped() const { return crop_width > 0 && crop_height > 0; }
  PixelFilterDesc filter;  // the film's reconstruction filter; box unless a file says otherwise
};

// One way in which a scene will not render as its file means: emlt approximates it, or
// cannot honour it at all. The Mitsuba loader records one for every such item (each is
// also a warning); `emlt info` sums them into its verdict and `--strict` refuses them.
struct Divergence {
  enum class Kind { Approximated, Unsupported } kind = Kind::Unsupported;
  std::string message;  // the warning's text, "<file>: line N: ..."
};

// What a scene file says about how to render it (Mitsuba's <integrator> and <sampler>, the
// JSON file's "integrator"), nothing more: the integrator, and the scene file options it
// sets (settings/scene_options.h) in the words of their flags; the engine's own defaults
// and the command line fill the rest (the render command).
struct SceneRenderRequest {
  std::string integrator;  // emlt's name for the file's integrator; empty: not said
  std::vector<std::pair<std::string, std::string>> options;  // ("--max-depth", "8"), ...

  // The value the file gives the option of `flag`, or nothing when it says nothing.
  std::optional<std::string> said(std::string_view flag) const;
  // Records `text` for `flag`, replacing what an earlier element said.
  void set(const std::string& flag, std::string text);
  // Options of the file's integrator that only it has (ERPT's chain counts and length, its
  // strategies, in their flags' words): the command line sets them through its registry
  // before its own flags. said() reports them too.
  std::vector<std::pair<std::string, std::string>> integrator_options;
  void set_integrator_option(const std::string& flag, std::string text);
};

struct SceneDescription {
  std::string source;  // file it came from
  std::vector<MaterialDesc> materials;
  std::vector<MeshDesc> meshes;
  std::vector<SphereDesc> spheres;
  EnvironmentDesc environment;
  std::vector<PointLightDesc> point_lights;
  std::vector<DirectionalLightDesc> directional_lights;
  std::vector<CollimatedLightDesc> collimated_lights;
  CameraDesc camera;
  SceneRenderRequest render;
  std::vector<std::string> warnings;
  std::vector<Divergence> divergences;  // each also in warnings
  // Shapes a loader could not read ("<shape type=\"heightfield\"> at line 12"), named in
  // the error when no geometry is left.
  std::vector<std::string> skipped_shapes;
  // Every file the scene was made from: the scene file, its includes, meshes, textures,
  // maps and spectra, in the order read (a checkpoint fingerprints their contents).
  std::vector<std::string> input_files;
  // Whether a direction that the geometric and the shading normal put on opposite sides of a
  // surface carries no light (Mitsuba's strictNormals true, and what its bidirectional
  // integrators always do). Off, the shading normal alone decides, as Mitsuba's path and
  // direct integrators do by default: light may leak through a coarse mesh's surface.
  // Every integrator reads it through the path and direct-lighting code they share.
  bool strict_normals = true;

  // "exact", or "approximated: N items, unsupported: M items" (either part alone when
  // the other count is zero).
  std::string verdict() const;
};

// "x", "y", "smaller", "larger" (the names both scene formats use); nullopt otherwise.
std::optional<CameraDesc::FovAxis> parse_fov_axis(const std::string& name);

// Builds the camera matrix from a look-at triple (Mitsuba's lookat semantics).
Mat4 look_at_matrix(const Vec3& origin, const Vec3& target, const Vec3& up);

}  // namespace emlt
