#pragma once
// The renderable scene: an Embree BVH over triangles (and over spheres when there are more
// than a few; fewer are tested directly, and so are the triangles of a scene of a few dozen,
// emlt/scene/direct_triangles.h), materials, the camera and the light set.
// Immutable after build(); safe to query from many threads.
#include <embree3/rtcore.h>

#include <memory>
#include <mutex>
#include <vector>

#include "emlt/scene/camera.h"
#include "emlt/scene/clearance_field.h"
#include "emlt/scene/description.h"
#include "emlt/scene/direct_triangles.h"
#include "emlt/scene/light_set.h"
#include "emlt/scene/point_light.h"
#include "emlt/scene/ray.h"
#include "emlt/scene/surface_bvh.h"

namespace emlt {

class CubeEnvironment;

struct SurfaceHit {
  Vec3 position{0.0f};
  Vec3 geometric_normal{0.0f};  // unit; triangle winding / sphere outward (flippable)
  Vec3 shading_normal{0.0f};    // unit; interpolated normal, same side as geometric
  Frame shading;                // z = shading_normal, s = dpdu made orthogonal to it (Mitsuba's)
  Vec2 uv{0.0f};
  // The mesh's per-vertex colours interpolated at the hit; black on surfaces without them.
  Rgb vertex_color{0.0f};
  // Surface derivatives with respect to uv (not normalised; an arbitrary tangent pair
  // when the uv mapping is degenerate). Bump mapping tilts the shading frame with them.
  // Filled on meshes whose material has a bump map or an anisotropic BSDF (the only
  // readers); zero on other meshes. Spheres always have them.
  Vec3 dpdu{0.0f}, dpdv{0.0f};
  float t = kInfinity;
  const Bsdf* bsdf = nullptr;   // never null for a valid hit
  const Light* light = nullptr; // the area light this point lies on, if emissive
  uint32_t geometry_id = 0, primitive_id = 0;

  // Radiance emitted from this point towards world direction w (zero if not emissive or w
  // is behind the emitting side).
  Rgb emitted(const Vec3& w) const;
};

struct SceneStats {
  size_t triangles = 0, dropped_degenerate_triangles = 0, spheres = 0, meshes = 0;
  size_t area_lights = 0, materials = 0;
  bool has_environment = false;
  // Whether rays test the triangles directly (DirectTriangles) instead of Embree's BVH.
  bool direct_triangles = false;
};

struct SceneBuildOptions {
  // Test the triangles of a scene of at most DirectTriangles::kMaxTriangles directly, as
  // the few spheres are, instead of through Embree's BVH. Off: every ray goes through the
  // BVH (`emlt render --bvh-only`, for comparisons; images differ only by rounding).
  bool direct_triangles = true;
  // Mistakes injected into the point lights, for the tests that must notice them.
  DeltaLightFaults delta_light_faults{};
  // Mistakes injected into the camera, for the tests that must notice them.
  CameraFaults camera_faults{};
};

class Scene {
 public:
  // Validates and builds; throws emlt::Error naming desc.source on unusable input
  // (no emitter, no geometry, zero/absurd resolution...). Degenerate triangles are dropped
  // and counted (a warning is appended to warnings()).
  static std::unique_ptr<Scene> build(SceneDescription desc, const SceneBuildOptions& options = {});
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  // Up to this many analytic spheres are intersected by Scene itself, ahead of the Embree
  // query, which is cheaper than any Embree geometry for them (docs/performance.md); a
  // scene with more puts them all in the BVH as a user geometry with the same root finding.
  static constexpr size_t kMaxDirectSpheres = 8;

  // On a hit, sets every field of `hit` (callers reuse one record along a path); on a
  // miss, leaves it as it was.
  bool intersect(const Ray& ray, SurfaceHit& hit) const;
  // The closest-hit query alone, without filling a SurfaceHit (bench/ray_rate.cpp times
  // it): Embree's BVH and the spheres kept outside it. On a hit, query.ray.tfar is the
  // distance and query.hit names the geometry and primitive.
  bool closest_hit(const Ray& ray, RTCRayHit& query) const;
  bool occluded(const Ray& ray) const;
  // How the shading normal turns as the point moves on the surface at `hit`: the map W
  // with dN = W dP for displacements dP in the tangent plane (the shape operator of the
  // shading normal, which the manifold walk's derivatives need). Spheres: +-(I - N N^T)/r;
  // smooth-shaded triangles: from the three vertex normals; flat triangles: zero. False
  // where the normal is not the smooth function of position this describes (a bump map
  // tilts it by a texture's slope).
  bool shading_normal_derivative(const SurfaceHit& hit, DMat3* dn_dp) const;
  // Mutual visibility of two surface points (each offset along its normal).
  bool visible(const Vec3& a, const Vec3& na, const Vec3& b, const Vec3& nb) const;
  // The surfaces near p, for queries that need the geometry itself. The visitor sees every triangle whose bounds
  // meet the ball B(p, radius) and every sphere (Embree 3's point queries skip spheres);
  // each call returns the radius to go on with (at most the one passed), so that the ball
  // can shrink as the visitor learns: a triangle meeting the final ball is always visited.
  // Alpha masks count as solid.
  struct NearbyVisitor {
    virtual ~NearbyVisitor() = default;
    // id: unique per triangle of the scene (a query may meet a triangle more than once).
    virtual float triangle(uint64_t id, const Vec3& a, const Vec3& b, const Vec3& c, float radius) = 0;
    virtual float sphere(const Vec3& center, float sphere_radius, float radius) = 0;
  };
  void visit_nearby(const Vec3& p, float radius, NearbyVisitor& visitor) const;
  // Every triangle (ids as visit_nearby's) and sphere in a hierarchy of our own, for
  // searches that are neither rays nor balls (surface_bvh.h). Built on the first call, by
  // whichever thread makes it, and kept: only the integrators that search it pay for it.
  const SurfaceBvh& surface_bvh() const;
  // Lower bounds on the distance to the nearest surface (clearance_field.h), over the
  // hierarchy's triangles and spheres; built on the first call and kept, as surface_bvh.
  const ClearanceField& clearance_field() const;

  const Camera& camera() const { return *camera_; }
  const LightSet& lights() const { return lights_; }
  const EnvironmentLight* environment() const { return lights_.environment(); }
  // The environment resampled onto a cube (cube_environment.h), for --env-sampler
  // cube-balanced; null without an environment. Built on the first call, as surface_bvh,
  // with that call's `resolution` (texels per face edge; 0: CubeEnvironment's choice): a
  // render asks with one resolution throughout, so later calls get the same cube.
  const CubeEnvironment* cube_environment(int resolution = 0) const;
  // The description as built, less its meshes' vertex and index arrays, which the scene's
  // geometry took over (each MeshDesc keeps its name, material and emission).
  const SceneDescription& description() const { return desc_; }
  // Whether a direction may carry light at a surface point whose geometric normal is n:
  // under strict normals (SceneDescription::strict_normals) only when n and the shading
  // normal put it on the same side (w_local_z: its shading-frame z); otherwise always, the
  // BSDF deciding by the shading normal alone.
  bool sides_agree(const Vec3& n, const Vec3& w_world, float w_local_z) const {
    return !desc_.strict_normals || glm::dot(n, w_world) * w_local_z > 0.0f;
  }
  const std::vector<std::string>& warnings() const { return desc_.warnings; }
  const SceneStats& stats() const { return stats_; }
  Vec3 bounds_center() const { return bounds_center_; }
  float bounds_radius() const { return bounds_radius_; }
  // Some mesh carries per-vertex colours (SurfaceHit::vertex_color is not always black).
  bool has_vertex_colors() const { return has_vertex_colors_; }

 private:
  Scene() = default;
  struct Geometry;  // per Embree geometry: kind, material, normals, uvs, lights
  // The bodies of closest_hit/intersect and occluded/visible, inlined into each.
  bool find_closest(const Ray& ray, RTCRayHit& query) const;
  bool find_occluder(const Ray& ray) const;
  // The nearest direct sphere within [ray.tmin, *tfar] (its id, and *tfar set to its
  // distance), or RTC_INVALID_GEOMETRY_ID; and whether any blocks the ray's segment.
  [[gnu::noinline]] uint32_t nearest_direct_sphere(const Ray& ray, float* tfar) const;
  [[gnu::noinline]] bool direct_sphere_occludes(const Ray& ray) const;
  // The nearest of direct_triangles_ within [ray.tmin, query.ray.tfar], written into query
  // as Embree would (tfar, geomID, primID, u, v); query is left as it was on a miss.
  [[gnu::noinline]] void nearest_direct_triangle(const Ray& ray, RTCRayHit& query) const;

  SceneDescription desc_;
  RTCDevice device_ = nullptr;
  RTCScene rtc_scene_ = nullptr;
  std::vector<Geometry> geometries_;
  std::vector<uint32_t> direct_spheres_;  // geometry ids of the spheres outside the BVH
  DirectTriangles direct_triangles_;      // every triangle, on a scene small enough; else empty
  std::unique_ptr<Camera> camera_;
  LightSet lights_;
  SceneStats stats_;
  Vec3 bounds_center_{0.0f};
  float bounds_radius_ = 1.0f;
  bool has_vertex_colors_ = false;
  mutable std::once_flag surface_bvh_built_;
  mutable SurfaceBvh surface_bvh_;
  mutable std::once_flag clearance_field_built_;
  mutable ClearanceField clearance_field_;
  mutable std::once_flag cube_environment_built_;
  mutable std::unique_ptr<CubeEnvironment> cube_environment_;
};

}  // namespace emlt
