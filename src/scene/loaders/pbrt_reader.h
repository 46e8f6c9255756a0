#pragma once
// pbrt-v4 scene files (internal to src/scene): the reader's state, shared by its parts.
// pbrt_loader.cpp reads directives, transforms and attributes; pbrt_camera.cpp the camera,
// film, sampler and integrator; pbrt_shapes.cpp, pbrt_materials.cpp, pbrt_textures.cpp and
// pbrt_lights.cpp what their names say. Everything a file says that emlt does not honour
// is a warning and a divergence (the verdict; --strict refuses it); what changes no image
// (a sampler's sequence, an acceleration structure) is a note.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "emlt/scene/description.h"
#include "src/scene/loaders/pbrt_parameters.h"
#include "src/scene/loaders/pbrt_tokenizer.h"

namespace emlt::pbrt {

// A place in a scene file, for messages.
struct Where {
  std::string file;
  int line = 0;
};

struct GraphicsState {
  Mat4 ctm{
      1.0f};  // pbrt's current transformation matrix: object to world (camera: world to camera)
  bool reverse_orientation = false;
  int material = -1;              // index into desc.materials; -1: pbrt's default (diffuse 0.5)
  bool interface = false;         // the current material is "interface": shapes bound media only
  std::optional<Rgb> area_light;  // radiance of AreaLightSource "diffuse" for the shapes after it
};

// Shapes declared between ObjectBegin and ObjectEnd, in world space of the declaration.
struct ObjectShapes {
  std::vector<MeshDesc> meshes;
  std::vector<SphereDesc> spheres;
};

class Reader {
 public:
  explicit Reader(const std::string& path);
  SceneDescription read();

  // Messages: "<file>: line N: ...".
  [[noreturn]] void fail(const Where& at, const std::string& problem) const;
  void warn(const Where& at, const std::string& message,
            Divergence::Kind kind = Divergence::Kind::Unsupported);
  void note(const Where& at, const std::string& message);
  // Every parameter of `params` that nothing read: one unsupported item each.
  void report_unused(const Params& params, const std::string& what);

  // A colour parameter (rgb, spectrum, blackbody) as linear RGB. Named spectra other than
  // the ones the caller handles and sampled spectra are items of the verdict (the fallback
  // is used); `illuminant`: pbrt normalises an emitter's spectrum to its luminance.
  Rgb color(const Params& params, const std::string& name, const Rgb& fallback);
  // A float or colour texture parameter: a constant, or a texture declared by Texture.
  TexturePtr texture(const Params& params, const std::string& name, const Rgb& fallback,
                     bool float_texture);
  // The same as a scalar when it is constant (nullopt for a varying texture).
  std::optional<float> constant_float(const Params& params, const std::string& name,
                                      float fallback);

  // A file a directive names: pbrt-v4 resolves names against the directory of the file it
  // was started on; one relative to the including file (`at`'s) is found too. Noted among
  // the scene's input files.
  std::string resolve(const Where& at, const std::string& name) const;

  // Moves a sphere by `to_world` (a non-uniform scale is an approximated item; a center
  // or radius that is no longer finite an error).
  void place_sphere(const Where& at, SphereDesc& sphere, const Mat4& to_world);

  // pbrt's material for shapes before any Material: two-sided diffuse 0.5.
  int default_material();

  // Parts (each in its own file).
  void camera(const Where& at, const std::string& type, const Params& params);
  void film(const Where& at, const std::string& type, const Params& params);
  void sampler(const Where& at, const std::string& type, const Params& params);
  void integrator(const Where& at, const std::string& type, const Params& params);
  void pixel_filter(const Where& at, const std::string& type, const Params& params);
  void shape(const Where& at, const std::string& type, const Params& params);
  void light(const Where& at, const std::string& type, const Params& params);
  void area_light(const Where& at, const std::string& type, const Params& params);
  // LightSource "infinite" with an image (pbrt_infinite_map.cpp).
  void infinite_map(const Where& at, const std::string& file_name, float scale);
  int material(const Where& at, const std::string& type, const Params& params,
               const std::string& name, bool* interface);
  void texture_declaration(const Where& at, const std::string& name, const std::string& kind,
                           const std::string& type, const Params& params);

  SceneDescription desc_;
  GraphicsState state_;
  std::vector<std::pair<GraphicsState, char>> stack_;  // 'a' attributes, 't' transform only
  std::vector<Where> opened_;                          // where each level of stack_ began
  std::map<std::string, Mat4> coordinate_systems_;
  std::map<std::string, int> named_materials_;
  // A NamedMaterial before its MakeNamedMaterial: pbrt-v4 resolves material names once the
  // whole scene is read, so the use is valid. The shapes meanwhile get a stand-in material
  // (its own BSDF object, found again by pointer) that the definition replaces.
  struct PendingMaterial {
    int index;         // the stand-in's entry in desc_.materials
    BsdfPtr stand_in;  // the stand-in's BSDF, also in any copy made for a cut-out shape
    Where first_use;
  };
  std::map<std::string, PendingMaterial> pending_materials_;
  std::map<std::string, bool> named_interfaces_;
  std::map<std::string, TexturePtr> float_textures_, color_textures_;
  std::map<std::string, ObjectShapes> objects_;
  ObjectShapes* current_object_ = nullptr;
  std::string current_object_name_;
  Where current_object_at_;
  bool in_world_ = false;
  bool camera_seen_ = false;
  bool ortho_ = false;        // an orthographic camera, whose window read() sizes
  bool filter_seen_ = false;  // a PixelFilter directive (else pbrt's default Gaussian)
  int default_material_ = -1;

 private:
  void read_file(const std::string& path, int depth);
  void directive(Tokenizer& tokens, const Token& word, int depth);
};

}  // namespace emlt::pbrt
