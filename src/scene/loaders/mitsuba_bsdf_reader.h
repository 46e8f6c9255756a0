#pragma once
// The Mitsuba 0.6 BSDF reader (internal to src/scene/loaders): one <bsdf> element, and the
// BSDFs nested in it, to a material. Its parts, by family:
// - mitsuba_bsdf.cpp: reading an element or <ref>, the parameters every family shares
//   (textures, IORs, energy conservation), nesting, and the dispatch from a plugin type to
//   the reader of its family;
// - mitsuba_bsdf_microfacet.cpp: the rough BSDFs' distribution and roughness;
// - mitsuba_bsdf_dielectric_conductor.cpp: dielectrics and conductors, smooth and rough;
// - mitsuba_bsdf_plastic_coating.cpp: plastics and coatings;
// - mitsuba_bsdf_classic.cpp: diffuse, rough diffuse, difftrans, phong, ward, and the
//   stand-ins for a BSDF emlt lacks;
// - mitsuba_bsdf_combining.cpp: twosided, mask, bumpmap, normalmap, mixturebsdf, blendbsdf.
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "emlt/scene/bsdf.h"
#include "emlt/scene/description.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/texture.h"
#include "src/scene/loaders/mitsuba_parser.h"

namespace emlt::mitsuba {

class BsdfReader {
 public:
  BsdfReader(const Document& doc, NamedObjects& named) : doc_(doc), named_(named) {}

  MaterialDesc read(pugi::xml_node node);

 private:
  // --- shared by every family (mitsuba_bsdf.cpp)

  // A parameter that may be a texture; counts the ones that vary over the surface and,
  // apart, those that read the mesh's vertex colours (which do not vary with uv).
  TexturePtr texture(Properties& props, const char* name, const Rgb& fallback);
  float ior(Properties& props, const char* name, float fallback, pugi::xml_node node);
  // Mitsuba's ensureEnergyConservation (on unless the scene turns it off): when the largest
  // component of a reflectance, or of the sum of a BSDF's reflectances, exceeds 1, they are
  // all scaled by 0.99 over that maximum. A constant's maximum is known here and applied; a
  // texture's is not (Mitsuba takes a bitmap's largest texel), so where a texture's lookups
  // over a grid of its period reach above 1 the difference is reported, not guessed at.
  void conserve_energy(Properties& props, pugi::xml_node node,
                       std::initializer_list<TexturePtr*> reflectances);
  // The nested BSDF of a wrapper; unnamed <texture> children are left to `textures`.
  MaterialDesc nested(pugi::xml_node node, Properties& props,
                      std::vector<pugi::xml_node>* textures = nullptr);
  void no_children(pugi::xml_node node, Properties& props);
  // The one dispatch: the reader of plugin `type`'s family.
  MaterialDesc build(const std::string& type, pugi::xml_node node, Properties& props);

  // --- microfacet parameters (mitsuba_bsdf_microfacet.cpp)

  MicrofacetType distribution(Properties& props, pugi::xml_node node);
  // Mitsuba's roughness: `alpha`, or both `alphaU` (along dp/du) and `alphaV`; either may
  // be a texture. `v` is null when the roughness is isotropic.
  struct Roughness {
    TexturePtr u, v;
  };
  Roughness roughness(Properties& props, pugi::xml_node node);
  TexturePtr alpha(Properties& props, pugi::xml_node node);

  // --- dielectrics and conductors (mitsuba_bsdf_dielectric_conductor.cpp)

  // A dielectric's specularReflectance and specularTransmittance (numbers or textures), each
  // scaled on its own to conserve energy, as Mitsuba's dielectrics do.
  std::pair<TexturePtr, TexturePtr> specular_tints(Properties& props, pugi::xml_node node);
  // Mitsuba's conductor parameters, divided by the exterior IOR like Mitsuba does.
  void conductor_ior(Properties& props, pugi::xml_node node, Rgb* eta, Rgb* k);
  // `dielectric` or `thindielectric`.
  BsdfPtr dielectric(const std::string& type, pugi::xml_node node, Properties& props);
  BsdfPtr rough_dielectric(pugi::xml_node node, Properties& props);
  BsdfPtr conductor(pugi::xml_node node, Properties& props);
  BsdfPtr rough_conductor(pugi::xml_node node, Properties& props);

  // --- plastics and coatings (mitsuba_bsdf_plastic_coating.cpp)

  // `plastic` or `roughplastic`.
  BsdfPtr plastic(const std::string& type, pugi::xml_node node, Properties& props);
  // Mitsuba's `coating` and `roughcoating`: a dielectric layer over the nested BSDF. Mitsuba
  // reads sigmaA and (rough) alpha as numbers or textures, specularReflectance as a colour
  // only, and refuses a textured one, an anisotropic roughness and equal IORs.
  MaterialDesc coating(const std::string& type, pugi::xml_node node, Properties& props);

  // --- diffuse and classic BSDFs, and stand-ins (mitsuba_bsdf_classic.cpp)

  BsdfPtr diffuse(pugi::xml_node node, Properties& props);
  BsdfPtr rough_diffuse(pugi::xml_node node, Properties& props);
  BsdfPtr diffuse_transmitter(pugi::xml_node node, Properties& props);
  BsdfPtr phong(pugi::xml_node node, Properties& props);
  BsdfPtr ward(pugi::xml_node node, Properties& props);
  // Mitsuba 3's `principled`, rendered as a diffuse of its base colour.
  BsdfPtr principled(pugi::xml_node node, Properties& props);
  // A type emlt does not know: a diffuse of its reflectance, or of 0.5.
  BsdfPtr unsupported(const std::string& type, pugi::xml_node node, Properties& props);

  // --- wrappers and weighted sums (mitsuba_bsdf_combining.cpp)

  MaterialDesc two_sided(pugi::xml_node node, Properties& props);
  MaterialDesc mask(pugi::xml_node node, Properties& props);
  MaterialDesc bump_map(pugi::xml_node node, Properties& props);
  // Mitsuba 3's bumpmap scales the height by its `scale` (0.6 nests a scale texture), and
  // by default darkens the shading where the bumped normal leans far from the true one
  // (use_shadowing_function), which emlt does not.
  TexturePtr mitsuba3_bump_height(pugi::xml_node node, Properties& props, TexturePtr height);
  // Mitsuba's `normalmap`: its one texture (of any name) holds tangent-space normals.
  MaterialDesc normal_map(pugi::xml_node node, Properties& props);
  // The nested BSDFs of a mixturebsdf or blendbsdf, in the file's order. A nested mask or
  // bump map is a property of the whole surface in emlt, not of one part of a sum.
  std::vector<BsdfPtr> parts(pugi::xml_node node, Properties& props);
  BsdfPtr mixture(pugi::xml_node node, Properties& props);
  BsdfPtr blend(pugi::xml_node node, Properties& props);

  const Document& doc_;
  NamedObjects& named_;
  int varying_textures_ = 0;
  int vertex_color_textures_ = 0;
};

}  // namespace emlt::mitsuba
