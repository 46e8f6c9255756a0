#pragma once
// Mitsuba 0.6 XML plumbing shared by the scene and BSDF readers (internal to src/scene):
// the parsed document with `$name` substitution and line numbers, and typed access to an
// element's named parameters (<float name="fov" value="45"/> ...).
#include <map>
#include <pugixml.hpp>
#include <set>
#include <string>
#include <vector>

#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/texture.h"
#include "src/scene/parameter_ranges.h"

namespace emlt::mitsuba {

class Document {
 public:
  // Parses the file; throws "<path>: malformed XML at line N: ..." on a syntax error.
  // Warnings go to `warnings`; those that say the scene will not render as Mitsuba
  // renders it also go to `divergences`.
  Document(std::string path, const SceneDefines& defines, std::vector<std::string>& warnings,
           std::vector<Divergence>& divergences);

  const std::string& path() const { return path_; }
  pugi::xml_node scene() const { return doc_.child("scene"); }
  // Whether the file is in Mitsuba 3's dialect (<scene version="2.x" or "3.x">): its
  // snake_case names are then read as the 0.6 ones they replace (mitsuba3_names.h), and the
  // readers apply the meanings Mitsuba 3 changed (docs/compatibility.md, "Mitsuba 3").
  bool mitsuba3() const { return mitsuba3_; }
  int line(pugi::xml_node node) const;

  // Attribute value with every `$name` replaced (defines override <default> values);
  // "" when absent. An unknown parameter is an error.
  std::string attribute(pugi::xml_node node, const char* name) const;
  bool has_attribute(pugi::xml_node node, const char* name) const {
    return !node.attribute(name).empty();
  }

  // "<bsdf type=\"diffuse\">" (messages carry the line separately)
  std::string describe(pugi::xml_node node) const;
  [[noreturn]] void fail(pugi::xml_node node, const std::string& problem) const;
  // A warning is a divergence from Mitsuba unless it is a Note (something emlt does as
  // Mitsuba does, said for the user's benefit): Unsupported when emlt ignores or skips
  // what the file asks for, Approximated when it renders something close instead.
  enum class Warning { Note, Approximated, Unsupported };
  void warn(pugi::xml_node node, const std::string& message,
            Warning kind = Warning::Unsupported) const;

  float to_float(pugi::xml_node node, const std::string& text) const;
  std::vector<float> to_floats(pugi::xml_node node, const std::string& text) const;

  // Registers <default name= value=> (called for each before anything else is read).
  void add_default(const std::string& name, const std::string& value) { defaults_[name] = value; }

 private:
  // Reports the plugins below `node` that Mitsuba 3 no longer has (mitsuba3_names.h).
  void check_mitsuba3_plugins(pugi::xml_node node) const;

  std::string path_;
  std::string text_;
  pugi::xml_document doc_;
  std::vector<size_t> line_starts_;
  const SceneDefines& defines_;
  std::map<std::string, std::string> defaults_;
  std::vector<std::string>& warnings_;
  std::vector<Divergence>& divergences_;
  bool mitsuba3_ = false;
};

// Objects declared with an id, for <ref id=...>.
struct NamedObjects {
  std::map<std::string, MaterialDesc> bsdfs;
  std::map<std::string, TexturePtr> textures;
};

// The named parameters of one element. Object children (bsdf, emitter, film, ref ...)
// are listed separately. Every parameter a reader does not ask for is reported by
// warn_unused(), so nothing in the file is dropped silently.
class Properties {
 public:
  Properties(const Document& doc, pugi::xml_node owner);

  bool has(const std::string& name) const { return values_.count(name) != 0; }
  // Element name of a parameter ("float", "rgb" ...), "" when absent.
  std::string kind_of(const std::string& name) const {
    auto it = values_.find(name);
    return it == values_.end() ? "" : it->second.name();
  }
  float get_float(const std::string& name, float fallback);
  int get_integer(const std::string& name, int fallback);
  // The same, refused outside `range` at the parameter's own line: "line 3: 'maxDepth'
  // must be a whole number from 0 to 100000, or -1 for unlimited (got -2)".
  float get_float(const std::string& name, float fallback, const loader::RealRange& range);
  int get_integer(const std::string& name, int fallback, const loader::IntegerRange& range);
  bool get_boolean(const std::string& name, bool fallback);
  std::string get_string(const std::string& name, const std::string& fallback);
  Rgb get_color(const std::string& name, const Rgb& fallback);
  // A colour or a texture (<texture>, or <ref name= id=> naming a declared one); plain
  // colours become constant textures. Defined in mitsuba_texture.cpp.
  TexturePtr get_texture(const std::string& name, const Rgb& fallback, NamedObjects& named);
  // Names of the parameters given as the element `kind` ("ref", "texture" ...).
  std::vector<std::string> names_of_kind(const std::string& kind) const;
  Vec3 get_point(const std::string& name, const Vec3& fallback);
  Mat4 get_transform(const std::string& name);  // identity when absent
  // The element that gives parameter `name` (for messages about its value); the owner
  // when the parameter is absent.
  pugi::xml_node node_of(const std::string& name) const;
  // Marks parameters that change nothing in this renderer (e.g. a film's pixel format).
  void ignore(std::initializer_list<const char*> names);
  // Marks every parameter used (an unsupported plugin reported once as a whole).
  void ignore_rest() {
    for (const auto& entry : values_) used_.insert(entry.first);
  }
  // Parameters that change only how Mitsuba draws its samples (a sampler's seed, a rough
  // BSDF's sampleVisible), never the converged image: those present are checked to be of
  // one of `kinds` with a well-formed value, marked used and named in one note (no item of
  // the verdict). `what` says what they steer ("sampling", "the sample sequence").
  void note_sampling_only(std::initializer_list<const char*> names, const std::string& what);
  // Whether `name` has been read or ignored already.
  bool used(const std::string& name) const { return used_.count(name) != 0; }
  // The parameter's name as the file spells it ("to_world" in a Mitsuba 3 file whose
  // readers ask for "toWorld"), for messages.
  std::string spelled(const std::string& name) const;

  const std::vector<pugi::xml_node>& objects() const { return objects_; }
  void warn_unused() const;

 private:
  pugi::xml_node take(const std::string& name, std::initializer_list<const char*> kinds);
  // Reports the colour forms of 0.6 that a Mitsuba 3 file cannot use (<srgb>, #rrggbb ...).
  void mitsuba3_colour_forms(pugi::xml_node node) const;
  [[noreturn]] void out_of_range(const std::string& name, const char* words) const;

  const Document& doc_;
  pugi::xml_node owner_;
  // By the 0.6 name the readers ask for; in a Mitsuba 3 file a parameter Mitsuba 3 does
  // not read is kept under a key no reader asks for ("mitsuba3:toWorld"), so that it is
  // reported unused rather than given its 0.6 meaning.
  std::map<std::string, pugi::xml_node> values_;
  std::set<std::string> used_;
  std::vector<pugi::xml_node> objects_;
};

// BSDF element (or <ref id=>) to a material: the BSDF, with `mask` and `bumpmap`
// wrappers unwrapped into the material's opacity and bump textures. Declarations with an
// id are added to `named`.
MaterialDesc read_bsdf(const Document& doc, pugi::xml_node node, NamedObjects& named,
                       std::vector<std::string>& warnings);

// <integrator> and <sampler> to what they say about rendering (mitsuba_render_request.cpp).
// read_integrator returns whether the integrator treats shading normals strictly
// (SceneDescription::strict_normals).
bool read_integrator(const Document& doc, pugi::xml_node node, SceneRenderRequest& request);
void read_sampler(const Document& doc, pugi::xml_node node, SceneRenderRequest& request);

// A `point`, `spot`, `directional` or `collimated` <emitter> into `desc`
// (mitsuba_delta_lights.cpp);
// false, reading nothing, for any other type.
bool read_delta_light(const Document& doc, pugi::xml_node node, NamedObjects& named,
                      SceneDescription& desc);

// <texture> element (or <ref id=>) to a texture; declarations with an id are added to
// `named`.
TexturePtr read_texture(const Document& doc, pugi::xml_node node, NamedObjects& named);

}  // namespace emlt::mitsuba
