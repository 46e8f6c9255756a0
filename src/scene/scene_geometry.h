#pragma once
// The geometry records Scene keeps beside its Embree scene, shared by the scene's build
// (scene_build.cpp) and its ray queries (scene.cpp).
#include <string>
#include <vector>

#include "emlt/scene/scene.h"
#include "emlt/scene/sphere_intersection.h"
#include "emlt/scene/texture.h"

namespace emlt {

struct Scene::Geometry {
  enum class Kind { Triangles, Sphere } kind = Kind::Triangles;
  std::string name;
  const Bsdf* bsdf = nullptr;
  const Texture* opacity = nullptr;  // Mitsuba `mask`: alpha-tested in Embree's filter
  const Texture* bump = nullptr;     // Mitsuba `bumpmap`: applied when a hit is filled
  bool anisotropic = false;          // the BSDF's frame must follow dp/du
  // Triangles (degenerate ones already removed).
  std::vector<Vec3> positions, normals;
  std::vector<Vec2> uvs;
  std::vector<Rgb> colors;  // per vertex; empty when the mesh has none
  std::vector<uint32_t> indices;
  std::vector<const Light*> lights;  // per triangle; empty when the mesh does not emit
  // Sphere.
  Vec3 center{0.0f};
  float radius = 0.0f;
  bool flip_normals = false;

  // Texture coordinates at a hit: interpolated from the vertices, per-triangle
  // barycentrics when the mesh has none, or Mitsuba's sphere parametrisation
  // (u = phi / 2pi, v = theta / pi).
  Vec2 uv_at(uint32_t primitive, float b1, float b2, const Vec3& position) const {
    if (kind == Kind::Sphere) {
      const Vec3 d = glm::normalize(position - center);
      float phi = std::atan2(d.y, d.x);
      if (phi < 0.0f) phi += kTwoPi;
      return {phi * kInvTwoPi, safe_acos(d.z) * kInvPi};
    }
    if (uvs.empty()) return {b1, b2};
    const uint32_t* tri = &indices[3 * size_t(primitive)];
    return (1.0f - b1 - b2) * uvs[tri[0]] + b1 * uvs[tri[1]] + b2 * uvs[tri[2]];
  }

  // The per-vertex colours interpolated barycentrically, as Mitsuba's `vertexcolors`
  // reads them; black where the surface has none.
  Rgb color_at(uint32_t primitive, float b1, float b2) const {
    if (colors.empty()) return Rgb(0.0f);
    const uint32_t* tri = &indices[3 * size_t(primitive)];
    return (1.0f - b1 - b2) * colors[tri[0]] + b1 * colors[tri[1]] + b2 * colors[tri[2]];
  }

  // The alpha test (Mitsuba's mask) on a candidate hit at distance t: true when the ray
  // passes through it. Embree calls it through a filter function on triangles; the sphere
  // callbacks call it themselves.
  bool lets_through(const Vec3& origin, const Vec3& direction, float t, uint32_t geometry_id,
                    uint32_t primitive, float b1, float b2) const;

  // The nearest root of this sphere in [tnear, tfar] that the alpha test keeps.
  bool sphere_hit(const Vec3& origin, const Vec3& direction, float tnear, float tfar,
                  uint32_t geometry_id, float* t) const {
    SphereRoots roots;
    if (!sphere_roots(center, radius, origin, direction, &roots)) return false;
    for (const float root : {roots.near, roots.far}) {
      if (!(root >= tnear && root <= tfar)) continue;
      if (opacity && lets_through(origin, direction, root, geometry_id, 0, 0.0f, 0.0f)) continue;
      *t = root;
      return true;
    }
    return false;
  }
};

}  // namespace emlt
