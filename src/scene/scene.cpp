#include "emlt/scene/scene.h"

#include <algorithm>
#include <bit>
#include <mutex>
#include <string>

#include <tbb/task_arena.h>

#include "emlt/core/error.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/shape_builders.h"
#include "emlt/scene/sphere_intersection.h"
#include "emlt/scene/texture.h"
#include "src/scene/parameter_ranges.h"

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

Rgb SurfaceHit::emitted(const Vec3& w) const {
  return light ? light->emitted(geometric_normal, w) : Rgb(0.0f);
}

namespace {

// Lane i of an Embree ray packet of width n: its origin and direction.
std::pair<Vec3, Vec3> ray_lane(RTCRayN* ray, unsigned n, unsigned i) {
  return {Vec3(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i)),
          Vec3(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i))};
}

uint64_t mix_bits(uint64_t h, uint64_t value) {
  // splitmix64's finaliser over the running state: every input bit affects every output bit.
  h ^= value + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebull;
  h ^= h >> 31;
  return h;
}

// The "random" number an alpha test compares the opacity against: a hash of the ray and
// the primitive it hit. Stochastic transparency (Mitsuba's mask) without a sampler
// dimension, and identical however the image is split across threads.
float alpha_test_threshold(const Vec3& origin, const Vec3& direction, uint32_t geometry,
                           uint32_t primitive) {
  uint64_t h = 0x5eedf00dull;
  for (int i = 0; i < 3; ++i) {
    h = mix_bits(h, std::bit_cast<uint32_t>(origin[i]));
    h = mix_bits(h, std::bit_cast<uint32_t>(direction[i]));
  }
  h = mix_bits(h, (uint64_t(geometry) << 32) | primitive);
  return float(h >> 40) * 0x1p-24f;
}

// Local uv derivatives of a triangle (pbrt's construction); a tangent pair of the plane
// when its uvs are degenerate.
void triangle_uv_derivatives(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec2& t0,
                             const Vec2& t1, const Vec2& t2, const Vec3& normal, Vec3* dpdu,
                             Vec3* dpdv) {
  const Vec2 duv02 = t0 - t2, duv12 = t1 - t2;
  const Vec3 dp02 = p0 - p2, dp12 = p1 - p2;
  const float det = duv02.x * duv12.y - duv02.y * duv12.x;
  if (std::abs(det) > 1e-12f) {
    const float inv = 1.0f / det;
    *dpdu = (duv12.y * dp02 - duv02.y * dp12) * inv;
    *dpdv = (duv02.x * dp12 - duv12.x * dp02) * inv;
    if (is_finite(*dpdu) && is_finite(*dpdv) && glm::length(glm::cross(*dpdu, *dpdv)) > 0.0f)
      return;
  }
  const Frame frame(normal);
  *dpdu = frame.s;
  *dpdv = frame.t;
}

// Tilts the shading normal as if the surface were displaced along it by the texture's
// height (Blinn 1978, in Mitsuba 0.6's form: the tangents lose their normal component
// and gain the height gradient instead). Central differences over about one texel.
// Returns the bumped dp/du, which orients the shading frame as in Mitsuba's bumpmap.
Vec3 apply_bump(const Texture& height, SurfaceHit& hit) {
  const Vec2 step = height.gradient_step();
  const Vec2 du(step.x, 0.0f), dv(0.0f, step.y);
  const float d_du =
      (height.eval_luminance(hit.uv + du) - height.eval_luminance(hit.uv - du)) / (2.0f * step.x);
  const float d_dv =
      (height.eval_luminance(hit.uv + dv) - height.eval_luminance(hit.uv - dv)) / (2.0f * step.y);
  const Vec3 n = hit.shading_normal;
  const Vec3 dpdu = hit.dpdu + n * (d_du - glm::dot(n, hit.dpdu));
  const Vec3 dpdv = hit.dpdv + n * (d_dv - glm::dot(n, hit.dpdv));
  Vec3 bumped = glm::cross(dpdu, dpdv);
  const float length = glm::length(bumped);
  if (!(length > 0.0f) || !std::isfinite(length)) return hit.dpdu;
  bumped /= length;
  if (glm::dot(bumped, n) < 0.0f) bumped = -bumped;
  hit.shading_normal = bumped;
  return dpdu;
}

// uv for a mesh that has none but needs some: the positions projected onto the plane of
// the bounding box's two longest sides, scaled to [0, 1].
std::vector<Vec2> planar_uvs(const std::vector<Vec3>& positions) {
  Vec3 lower(kInfinity), upper(-kInfinity);
  for (const Vec3& p : positions) lower = glm::min(lower, p), upper = glm::max(upper, p);
  const Vec3 extent = glm::max(upper - lower, Vec3(1e-20f));
  int a = 0, b = 1, c = 2;  // sorted by extent, longest first
  if (extent[b] > extent[a]) std::swap(a, b);
  if (extent[c] > extent[b]) std::swap(b, c);
  if (extent[b] > extent[a]) std::swap(a, b);
  std::vector<Vec2> uvs;
  uvs.reserve(positions.size());
  for (const Vec3& p : positions)
    uvs.emplace_back((p[a] - lower[a]) / extent[a], (p[b] - lower[b]) / extent[b]);
  return uvs;
}

// The film's limit for descriptions that no loader checked (the loaders refuse a side
// outside it with the file's key or line), stated in words in validate_camera.
constexpr int kMaxResolution = loader::kFilmSideRange.high;
constexpr int64_t kMaxPixels = int64_t(kMaxResolution) * kMaxResolution;

// Embree reports errors through a callback; the build collects them and fails on any.
struct EmbreeErrors {
  std::mutex mutex;
  std::string first;
};

void record_embree_error(void* user, RTCError code, const char* message) {
  auto* errors = static_cast<EmbreeErrors*>(user);
  std::lock_guard lock(errors->mutex);
  if (errors->first.empty())
    errors->first = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
}

void validate_camera(const SceneDescription& desc) {
  const CameraDesc& camera = desc.camera;
  if (camera.width <= 0 || camera.height <= 0 || camera.width > kMaxResolution ||
      camera.height > kMaxResolution || int64_t(camera.width) * camera.height > kMaxPixels)
    throw file_error(desc.source, "unusable image resolution " + std::to_string(camera.width) +
                                      "x" + std::to_string(camera.height) +
                                      " (each side must be 1 to 16384 pixels)");
  if (!is_finite_matrix(camera.to_world))
    throw file_error(desc.source, "camera transform contains NaN or infinite values");
  if (!(camera.fov_degrees > 0.0f && camera.fov_degrees < 180.0f))
    throw file_error(desc.source, "camera field of view must lie in (0, 180) degrees");
  if (!(camera.aperture_radius >= 0.0f) || !(camera.focus_distance > 0.0f) ||
      !std::isfinite(camera.aperture_radius) || !std::isfinite(camera.focus_distance))
    throw file_error(desc.source, "camera aperture radius must be >= 0 and focus distance > 0");
}

void validate_emission(const SceneDescription& desc, const std::string& shape, const Rgb& e) {
  if (!is_finite(e) || e.x < 0.0f || e.y < 0.0f || e.z < 0.0f)
    throw file_error(desc.source, "shape '" + shape + "' has a negative or non-finite emission");
}

}  // namespace

bool Scene::Geometry::lets_through(const Vec3& origin, const Vec3& direction, float t,
                                   uint32_t geometry_id, uint32_t primitive, float b1,
                                   float b2) const {
  const float alpha = opacity->eval_luminance(uv_at(primitive, b1, b2, origin + t * direction));
  if (alpha >= 1.0f) return false;
  return !(alpha > 0.0f) ||
         alpha_test_threshold(origin, direction, geometry_id, primitive) >= alpha;
}

std::unique_ptr<Scene> Scene::build(SceneDescription desc, const SceneBuildOptions& options) {
  std::unique_ptr<Scene> scene(new Scene());
  Scene& s = *scene;
  s.desc_ = std::move(desc);
  SceneDescription& d = s.desc_;
  validate_camera(d);

  // Emissive spheres become triangle meshes so every area light is a TriangleLight.
  std::vector<SphereDesc> analytic_spheres;
  for (SphereDesc& sphere : d.spheres) {
    if (!(sphere.radius > 0.0f) || !std::isfinite(sphere.radius) || !is_finite(sphere.center))
      throw file_error(d.source, "sphere '" + sphere.name + "' has an invalid center or radius");
    validate_emission(d, sphere.name, sphere.emission);
    if (is_black(sphere.emission)) {
      analytic_spheres.push_back(sphere);
      continue;
    }
    MeshDesc mesh = make_sphere_mesh(sphere.center, sphere.radius, sphere.flip_normals);
    mesh.name = sphere.name + " (tessellated emissive sphere)";
    mesh.material = sphere.material;
    mesh.emission = sphere.emission;
    d.meshes.push_back(std::move(mesh));
  }
  d.spheres = analytic_spheres;  // the description lists each shape once, as built

  // Shapes without a material get Mitsuba's default BSDF (diffuse, reflectance 0.5).
  int default_material = -1;
  auto material_for = [&](int index, const std::string& shape) -> const MaterialDesc* {
    if (index >= int(d.materials.size()) || (index >= 0 && !d.materials[size_t(index)].bsdf))
      throw file_error(d.source, "shape '" + shape + "' refers to a missing material");
    if (index >= 0) return &d.materials[size_t(index)];
    if (default_material < 0) {
      default_material = int(d.materials.size());
      d.materials.push_back({"default diffuse", make_two_sided(make_lambertian(Rgb(0.5f)))});
    }
    d.warnings.push_back(d.source + ": shape '" + shape +
                         "' has no material; using a two-sided diffuse of reflectance 0.5");
    return &d.materials[size_t(default_material)];
  };
  auto assign_material = [&](Geometry& g, int index, const std::string& shape) {
    const MaterialDesc* material = material_for(index, shape);
    g.bsdf = material->bsdf.get();
    g.opacity = material->opacity.get();
    g.bump = material->bump.get();
    g.anisotropic = g.bsdf->is_anisotropic();
  };
  // The default material may be appended while shapes are read; reserving keeps the
  // MaterialDesc pointers above valid.
  d.materials.reserve(d.materials.size() + 1);

  Vec3 lower(kInfinity), upper(-kInfinity);
  std::vector<LightPtr> lights;

  for (MeshDesc& mesh : d.meshes) {
    validate_emission(d, mesh.name, mesh.emission);
    if (mesh.indices.size() % 3 != 0)
      throw file_error(d.source, "mesh '" + mesh.name + "': index count is not a multiple of 3");
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
      throw file_error(d.source,
                       "mesh '" + mesh.name + "': normal count differs from vertex count");
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
      throw file_error(d.source, "mesh '" + mesh.name + "': uv count differs from vertex count");
    ++s.stats_.meshes;

    Geometry g;
    g.kind = Geometry::Kind::Triangles;
    g.name = mesh.name;
    assign_material(g, mesh.material, mesh.name);
    g.uvs = std::move(mesh.uvs);
    if (g.uvs.empty() && mesh.material >= 0 && d.materials[size_t(mesh.material)].textured) {
      g.uvs = planar_uvs(mesh.positions);
      d.warnings.push_back(d.source + ": mesh '" + mesh.name +
                           "' has no texture coordinates but a textured material; using a "
                           "planar projection onto its bounding box's two longest sides");
    }
    const bool emissive = !is_black(mesh.emission);
    // The kept triangles are written back over the mesh's own indices (never ahead of the
    // one being read), which then become the geometry's.
    size_t kept = 0;
    for (size_t i = 0; i < mesh.indices.size(); i += 3) {
      uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
      if (a >= mesh.positions.size() || b >= mesh.positions.size() || c >= mesh.positions.size())
        throw file_error(d.source, "mesh '" + mesh.name + "': triangle " + std::to_string(i / 3) +
                                       " has a vertex index out of range");
      Vec3 cross = glm::cross(mesh.positions[b] - mesh.positions[a],
                              mesh.positions[c] - mesh.positions[a]);
      // Mitsuba and pbrt orient a surface with vertex normals by those normals, not by
      // its winding: they decide which side emits and which side a one-sided BSDF
      // reflects on. Re-winding such a triangle to agree with its normals (taken at the
      // centroid) lets the rest of the renderer trust the winding alone.
      if (!mesh.normals.empty() &&
          glm::dot(cross, mesh.normals[a] + mesh.normals[b] + mesh.normals[c]) < 0.0f) {
        std::swap(b, c);
        cross = -cross;
      }
      const Vec3 &pa = mesh.positions[a], &pb = mesh.positions[b], &pc = mesh.positions[c];
      const float length = glm::length(cross);
      if (!is_finite(pa) || !is_finite(pb) || !is_finite(pc) || !(length > 0.0f) ||
          !std::isfinite(length) || !is_finite(cross / length)) {
        ++s.stats_.dropped_degenerate_triangles;
        continue;
      }
      mesh.indices[kept] = a, mesh.indices[kept + 1] = b, mesh.indices[kept + 2] = c;
      kept += 3;
      for (const Vec3* p : {&pa, &pb, &pc}) {
        lower = glm::min(lower, *p);
        upper = glm::max(upper, *p);
      }
      if (emissive) {
        lights.push_back(std::make_unique<TriangleLight>(pa, pb, pc, mesh.emission));
        g.lights.push_back(lights.back().get());
      }
    }
    // The mesh's arrays move to the geometry (on a million-triangle mesh a second copy of
    // each, held through the render, was a quarter of the heap). One spare float after the
    // positions lets Embree read them in place (see the BVH below).
    mesh.indices.resize(kept);
    g.indices = std::move(mesh.indices);
    mesh.positions.reserve(mesh.positions.size() + 1);
    g.positions = std::move(mesh.positions);
    g.normals = std::move(mesh.normals);
    s.stats_.triangles += g.indices.size() / 3;
    s.stats_.area_lights += g.lights.size();
    if (!g.indices.empty()) s.geometries_.push_back(std::move(g));
  }
  if (s.stats_.dropped_degenerate_triangles > 0)
    d.warnings.push_back(d.source + ": " + std::to_string(s.stats_.dropped_degenerate_triangles) +
                         " degenerate triangles dropped");

  for (const SphereDesc& sphere : analytic_spheres) {
    Geometry g;
    g.kind = Geometry::Kind::Sphere;
    g.name = sphere.name;
    assign_material(g, sphere.material, sphere.name);
    g.center = sphere.center;
    g.radius = sphere.radius;
    g.flip_normals = sphere.flip_normals;
    lower = glm::min(lower, sphere.center - sphere.radius);
    upper = glm::max(upper, sphere.center + sphere.radius);
    s.geometries_.push_back(std::move(g));
    ++s.stats_.spheres;
  }
  if (s.geometries_.empty()) {
    std::string skipped;
    for (size_t i = 0; i < d.skipped_shapes.size() && i < 4; ++i)
      skipped += (i ? ", " : "") + d.skipped_shapes[i];
    if (d.skipped_shapes.size() > 4)
      skipped += " and " + std::to_string(d.skipped_shapes.size() - 4) + " more";
    throw file_error(d.source, skipped.empty() ? std::string("scene has no geometry")
                                               : "scene has no geometry: every shape was skipped (" +
                                                     skipped + ")");
  }
  s.stats_.materials = d.materials.size();

  s.bounds_center_ = 0.5f * (lower + upper);
  s.bounds_radius_ = std::max(0.5f * glm::length(upper - lower), 1e-3f);

  // Environment.
  const EnvironmentDesc& env = d.environment;
  std::unique_ptr<EnvironmentLight> environment;
  if (env.kind == EnvironmentDesc::Kind::Constant) {
    if (!is_finite(env.radiance) || env.radiance.x < 0 || env.radiance.y < 0 || env.radiance.z < 0)
      throw file_error(d.source, "environment radiance must be finite and non-negative");
    if (!is_black(env.radiance)) environment = std::make_unique<ConstantEnvironment>(env.radiance);
  } else if (env.kind == EnvironmentDesc::Kind::Map) {
    if (!std::isfinite(env.scale) || env.scale < 0.0f || !is_finite_matrix(env.to_world))
      throw file_error(d.source, "environment map scale/transform must be finite (scale >= 0)");
    Image map = env.map.pixels.empty() ? read_image(env.map_path) : env.map;
    if (map.width <= 0 || map.height <= 0)
      throw file_error(d.source, "environment map '" + env.map_path + "' is empty");
    if (env.scale > 0.0f)
      environment = std::make_unique<EnvironmentMap>(std::move(map), env.scale, Mat3(env.to_world));
  }
  if (environment) {
    environment->set_scene_bounds(s.bounds_center_, s.bounds_radius_);
    s.stats_.has_environment = true;
    lights.push_back(std::move(environment));
  }
  Rgb total_power(0.0f);
  for (const LightPtr& light : lights) total_power += light->power();
  if (lights.empty() || !(max_component(total_power) > 0.0f))
    throw file_error(d.source, "scene has no emitter (no emissive shape and no environment)");
  s.lights_ = LightSet(std::move(lights));

  s.camera_ = std::make_unique<Camera>(d.camera);

  // Embree.
  EmbreeErrors errors;
  s.device_ = rtcNewDevice(nullptr);
  if (!s.device_) throw file_error(d.source, "could not create the Embree device");
  rtcSetDeviceErrorFunction(s.device_, record_embree_error, &errors);
  // `errors` dies with this frame, also when a throw leaves it.
  struct DetachErrors {
    RTCDevice device;
    ~DetachErrors() { rtcSetDeviceErrorFunction(device, nullptr, nullptr); }
  } detach_errors{s.device_};
  s.rtc_scene_ = rtcNewScene(s.device_);
  // Robust mode makes triangle tests watertight, so paths never leak through shared edges
  // (glass and closed meshes rely on it); the cost is small.
  rtcSetSceneFlags(s.rtc_scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(s.rtc_scene_, RTC_BUILD_QUALITY_HIGH);
  // The sphere callbacks. Lambdas in a member function may name the private Geometry type;
  // Embree passes N = 1 from rtcIntersect1/rtcOccluded1, the loops serve any N.
  const RTCBoundsFunction sphere_bounds = [](const RTCBoundsFunctionArguments* args) {
    const auto* sphere = static_cast<const Geometry*>(args->geometryUserPtr);
    // A relative margin of a few float spacings, so that rounding in the box cannot cut
    // off a grazing hit that the root finding accepts.
    const Vec3 extent = Vec3(sphere->radius) + 1e-6f * (glm::abs(sphere->center) + sphere->radius);
    const Vec3 lower = sphere->center - extent, upper = sphere->center + extent;
    *args->bounds_o = RTCBounds{lower.x, lower.y, lower.z, 0.0f, upper.x, upper.y, upper.z, 0.0f};
  };
  const RTCIntersectFunctionN sphere_intersect = [](const RTCIntersectFunctionNArguments* args) {
    const auto* sphere = static_cast<const Geometry*>(args->geometryUserPtr);
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
    const unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
      if (args->valid[i] != -1) continue;
      const auto [origin, direction] = ray_lane(ray, n, i);
      float t;
      if (!sphere->sphere_hit(origin, direction, RTCRayN_tnear(ray, n, i), RTCRayN_tfar(ray, n, i),
                              args->geomID, &t))
        continue;
      // Scene::intersect re-derives the point, normal and uv from t; the normal here is
      // for other callers of the Embree scene (unnormalised, as Embree's own).
      const Vec3 normal = origin + t * direction - sphere->center;
      RTCRayN_tfar(ray, n, i) = t;
      RTCHitN_Ng_x(hit, n, i) = normal.x;
      RTCHitN_Ng_y(hit, n, i) = normal.y;
      RTCHitN_Ng_z(hit, n, i) = normal.z;
      RTCHitN_u(hit, n, i) = 0.0f;
      RTCHitN_v(hit, n, i) = 0.0f;
      RTCHitN_primID(hit, n, i) = args->primID;
      RTCHitN_geomID(hit, n, i) = args->geomID;
      RTCHitN_instID(hit, n, i, 0) = args->context->instID[0];
    }
  };
  const RTCOccludedFunctionN sphere_occluded = [](const RTCOccludedFunctionNArguments* args) {
    const auto* sphere = static_cast<const Geometry*>(args->geometryUserPtr);
    RTCRayN* ray = args->ray;
    const unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
      if (args->valid[i] != -1) continue;
      const auto [origin, direction] = ray_lane(ray, n, i);
      float t;
      if (sphere->sphere_hit(origin, direction, RTCRayN_tnear(ray, n, i), RTCRayN_tfar(ray, n, i),
                             args->geomID, &t))
        RTCRayN_tfar(ray, n, i) = -kInfinity;  // Embree's mark of an occluded ray
    }
  };
  // A handful of spheres costs less tested one by one in Scene::intersect and occluded
  // than through any Embree geometry (see kMaxDirectSpheres); more go into the BVH.
  size_t sphere_count = 0;
  for (const Geometry& g : s.geometries_) sphere_count += g.kind == Geometry::Kind::Sphere;
  const bool spheres_direct = sphere_count <= kMaxDirectSpheres;
  for (size_t id = 0; id < s.geometries_.size(); ++id) {
    const Geometry& g = s.geometries_[id];
    if (g.kind == Geometry::Kind::Sphere && spheres_direct) {
      s.direct_spheres_.push_back(uint32_t(id));
      continue;
    }
    RTCGeometry geometry;
    if (g.kind == Geometry::Kind::Triangles) {
      geometry = rtcNewGeometry(s.device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      // Embree reads the geometry's own arrays instead of copies (they live as long as the
      // scene). It loads a vertex with 16-byte reads, so the last one needs a float after it:
      // the capacity reserved above.
      static_assert(sizeof(Vec3) == 3 * sizeof(float));
      rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                 g.positions.data(), 0, sizeof(Vec3), g.positions.size());
      rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                 g.indices.data(), 0, 3 * sizeof(uint32_t), g.indices.size() / 3);
    } else {
      // A user geometry with our own root finding (sphere_intersection.h): Embree's
      // point-sphere primitive goes through its generic curve code, which cost a third
      // of the render's instructions on a scene with two spheres.
      geometry = rtcNewGeometry(s.device_, RTC_GEOMETRY_TYPE_USER);
      rtcSetGeometryUserPrimitiveCount(geometry, 1);
      rtcSetGeometryBoundsFunction(geometry, sphere_bounds, nullptr);
      rtcSetGeometryIntersectFunction(geometry, sphere_intersect);
      rtcSetGeometryOccludedFunction(geometry, sphere_occluded);
    }
    rtcSetGeometryUserData(geometry, const_cast<Geometry*>(&g));
    if (g.opacity && g.kind == Geometry::Kind::Triangles) {
      // Alpha test: Embree calls this for every candidate hit, before accepting it, in
      // both closest-hit and occlusion queries. A lambda in a member function may name
      // the private Geometry type.
      const RTCFilterFunctionN alpha_test = [](const RTCFilterFunctionNArguments* args) {
        const auto* surface = static_cast<const Geometry*>(args->geometryUserPtr);
        for (unsigned i = 0; i < args->N; ++i) {
          if (args->valid[i] != -1) continue;
          const auto [origin, direction] = ray_lane(args->ray, args->N, i);
          if (surface->lets_through(
                  origin, direction, RTCRayN_tfar(args->ray, args->N, i),
                  RTCHitN_geomID(args->hit, args->N, i), RTCHitN_primID(args->hit, args->N, i),
                  RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)))
            args->valid[i] = 0;  // passes through: Embree looks for the next hit
        }
      };
      rtcSetGeometryIntersectFilterFunction(geometry, alpha_test);
      rtcSetGeometryOccludedFilterFunction(geometry, alpha_test);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(s.rtc_scene_, geometry, unsigned(id));
    rtcReleaseGeometry(geometry);
  }
  // Built inside an explicit arena: when Embree's build ran in the calling thread's implicit
  // arena, oneTBB's worker threads stayed parked there and joined the renderer's first arena
  // only 50-130 ms later, while one thread rendered alone (a tenth of a short render's wall
  // time at 2 threads; measured with perf's per-thread timeline).
  tbb::task_arena build_arena;
  build_arena.execute([&] { rtcCommitScene(s.rtc_scene_); });
  // A few dozen triangles are tested directly, like the few spheres (direct_triangles.h).
  // The BVH stays built for the point queries of visit_nearby. Alpha masks need Embree's
  // filter, and spheres in the BVH need its traversal.
  bool direct_triangles = options.direct_triangles && DirectTriangles::available() &&
                          spheres_direct && s.stats_.triangles <= DirectTriangles::kMaxTriangles;
  for (const Geometry& g : s.geometries_) direct_triangles &= g.opacity == nullptr;
  s.stats_.direct_triangles = direct_triangles;
  if (direct_triangles) {
    for (size_t id = 0; id < s.geometries_.size(); ++id) {
      const Geometry& g = s.geometries_[id];
      if (g.kind != Geometry::Kind::Triangles) continue;
      for (size_t i = 0; i < g.indices.size(); i += 3)
        s.direct_triangles_.add(uint32_t(id), uint32_t(i / 3), g.positions[g.indices[i]],
                                g.positions[g.indices[i + 1]], g.positions[g.indices[i + 2]]);
    }
  }
  if (!errors.first.empty()) throw file_error(d.source, errors.first);
  return scene;
}

Scene::~Scene() {
  if (rtc_scene_) rtcReleaseScene(rtc_scene_);
  if (device_) rtcReleaseDevice(device_);
}

// The direct spheres' loops are calls of their own, so that a scene without spheres pays
// one test of an empty vector for them, not a larger inlined body.
uint32_t Scene::nearest_direct_sphere(const Ray& ray, float* tfar) const {
  uint32_t sphere = RTC_INVALID_GEOMETRY_ID;
  for (const uint32_t id : direct_spheres_) {
    float t;
    if (geometries_[id].sphere_hit(ray.origin, ray.direction, ray.tmin, *tfar, id, &t))
      *tfar = t, sphere = id;
  }
  return sphere;
}

void Scene::nearest_direct_triangle(const Ray& ray, RTCRayHit& query) const {
  DirectTriangleHit hit;
  if (!direct_triangles_.nearest(ray, &query.ray.tfar, &hit)) return;
  query.hit.geomID = hit.geometry;
  query.hit.primID = hit.primitive;
  query.hit.u = hit.u;
  query.hit.v = hit.v;
}

bool Scene::direct_sphere_occludes(const Ray& ray) const {
  float t;
  for (const uint32_t id : direct_spheres_)
    if (geometries_[id].sphere_hit(ray.origin, ray.direction, ray.tmin, ray.tmax, id, &t))
      return true;
  return false;
}

// Inlined into each of its callers here, as the Embree queries were before the spheres.
[[gnu::always_inline]] inline bool Scene::find_closest(const Ray& ray, RTCRayHit& query) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  query.ray.org_x = ray.origin.x, query.ray.org_y = ray.origin.y, query.ray.org_z = ray.origin.z;
  query.ray.dir_x = ray.direction.x, query.ray.dir_y = ray.direction.y,
  query.ray.dir_z = ray.direction.z;
  query.ray.tnear = ray.tmin;
  query.ray.tfar = ray.tmax;
  query.ray.time = 0.0f;
  query.ray.mask = ~0u;
  query.ray.id = 0;
  query.ray.flags = 0;
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  // The spheres outside the BVH first: a hit shortens the segment Embree traverses.
  const uint32_t sphere = direct_spheres_.empty() ? RTC_INVALID_GEOMETRY_ID
                                                  : nearest_direct_sphere(ray, &query.ray.tfar);
  if (!direct_triangles_.empty())
    nearest_direct_triangle(ray, query);
  else
    rtcIntersect1(rtc_scene_, &context, &query);
  if (query.hit.geomID != RTC_INVALID_GEOMETRY_ID) return true;
  if (sphere == RTC_INVALID_GEOMETRY_ID) return false;
  query.hit.geomID = sphere;  // nothing in the BVH is nearer than the sphere
  query.hit.primID = 0;
  query.hit.u = query.hit.v = 0.0f;
  return true;
}

bool Scene::closest_hit(const Ray& ray, RTCRayHit& query) const {
  return find_closest(ray, query);
}

bool Scene::intersect(const Ray& ray, SurfaceHit& hit) const {
  RTCRayHit query;
  if (!find_closest(ray, query)) return false;

  const Geometry& g = geometries_[query.hit.geomID];
  hit.t = query.ray.tfar;
  hit.geometry_id = query.hit.geomID;
  hit.primitive_id = query.hit.primID;
  hit.bsdf = g.bsdf;
  hit.light = nullptr;

  if (g.kind == Geometry::Kind::Sphere) {
    // Re-project onto the sphere: cheaper than refining t, and keeps spawned rays on the
    // correct side of the surface.
    Vec3 n = glm::normalize(ray.origin + hit.t * ray.direction - g.center);
    hit.position = g.center + g.radius * n;
    hit.uv = g.uv_at(0, 0.0f, 0.0f, hit.position);
    // d/du and d/dv of center + r (sin v' cos u', sin v' sin u', cos v'), u' = 2 pi u,
    // v' = pi v; at the poles the tangent pair of the normal's frame.
    const float sin_theta = std::sqrt(n.x * n.x + n.y * n.y);
    if (sin_theta > 1e-6f) {
      const float cos_phi = n.x / sin_theta, sin_phi = n.y / sin_theta;
      hit.dpdu = kTwoPi * g.radius * Vec3(-n.y, n.x, 0.0f);
      hit.dpdv = kPi * g.radius * Vec3(n.z * cos_phi, n.z * sin_phi, -sin_theta);
    } else {
      const Frame frame(n);
      hit.dpdu = frame.s, hit.dpdv = frame.t;
    }
    if (g.flip_normals) n = -n;
    hit.geometric_normal = hit.shading_normal = n;
  } else {
    const uint32_t* tri = &g.indices[3 * size_t(hit.primitive_id)];
    const float u = query.hit.u, v = query.hit.v, w = 1.0f - u - v;
    const Vec3 &p0 = g.positions[tri[0]], &p1 = g.positions[tri[1]], &p2 = g.positions[tri[2]];
    // Barycentric interpolation is more accurate than origin + t * direction.
    hit.position = w * p0 + u * p1 + v * p2;
    const Vec3 ng = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    hit.geometric_normal = ng;
    Vec3 ns = ng;
    if (!g.normals.empty()) {
      const Vec3 interpolated =
          w * g.normals[tri[0]] + u * g.normals[tri[1]] + v * g.normals[tri[2]];
      const float length = glm::length(interpolated);
      if (length > 1e-12f && std::isfinite(length)) {
        ns = interpolated / length;
        if (glm::dot(ns, ng) < 0.0f) ns = -ns;
      }
    }
    hit.shading_normal = ns;
    hit.uv = g.uv_at(hit.primitive_id, u, v, hit.position);
    // Only a bump map and an anisotropic BSDF read the derivatives; working them out for
    // every hit cost a tenth of this function.
    if (!g.bump && !g.anisotropic)
      hit.dpdu = hit.dpdv = Vec3(0.0f);
    else if (g.uvs.empty())
      hit.dpdu = p1 - p0, hit.dpdv = p2 - p0;  // uv are the barycentrics themselves
    else
      triangle_uv_derivatives(p0, p1, p2, g.uvs[tri[0]], g.uvs[tri[1]], g.uvs[tri[2]], ng,
                              &hit.dpdu, &hit.dpdv);
    if (!g.lights.empty()) hit.light = g.lights[hit.primitive_id];
  }
  // Under an anisotropic BSDF the shading frame's s axis follows dp/du as Mitsuba's does:
  // for a sphere its parallels, for a mesh with uvs the direction of increasing u, for one
  // without, p1 - p0 (Mitsuba's choice too). Other BSDFs keep the normal's own frame,
  // which is cheaper and leaves their random streams as they were.
  const Vec3 tangent = g.bump ? apply_bump(*g.bump, hit) : hit.dpdu;
  hit.shading = g.anisotropic ? Frame(hit.shading_normal, tangent) : Frame(hit.shading_normal);
  return true;
}

[[gnu::always_inline]] inline bool Scene::find_occluder(const Ray& ray) const {
  if (!direct_spheres_.empty() && direct_sphere_occludes(ray)) return true;
  if (!direct_triangles_.empty()) return direct_triangles_.any(ray);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay query;
  query.org_x = ray.origin.x, query.org_y = ray.origin.y, query.org_z = ray.origin.z;
  query.dir_x = ray.direction.x, query.dir_y = ray.direction.y, query.dir_z = ray.direction.z;
  query.tnear = ray.tmin;
  query.tfar = ray.tmax;
  query.time = 0.0f;
  query.mask = ~0u;
  query.id = 0;
  query.flags = 0;
  rtcOccluded1(rtc_scene_, &context, &query);
  return query.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

bool Scene::occluded(const Ray& ray) const {
  return find_occluder(ray);
}

bool Scene::visible(const Vec3& a, const Vec3& na, const Vec3& b, const Vec3& nb) const {
  const Vec3 origin = offset_ray_origin(a, na, b - a);
  const Vec3 target = offset_ray_origin(b, nb, a - b);
  const Vec3 delta = target - origin;
  const float distance = glm::length(delta);
  if (!(distance > 0.0f)) return true;
  // The relative shortening keeps the far surface itself from counting as a blocker.
  return !find_occluder(Ray{origin, delta / distance, 0.0f, distance * (1.0f - 1e-4f)});
}

void Scene::visit_nearby(const Vec3& p, float radius, NearbyVisitor& visitor) const {
  struct Query {
    const Scene* scene;
    NearbyVisitor* visitor;
  } query_data{this, &visitor};
  RTCPointQuery query;
  query.x = p.x, query.y = p.y, query.z = p.z;
  query.radius = radius;
  query.time = 0.0f;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  // Embree visits every primitive whose bounds meet the current ball; the visitor may shrink it.
  const RTCPointQueryFunction visit = [](RTCPointQueryFunctionArguments* args) -> bool {
    const auto* q = static_cast<const Query*>(args->userPtr);
    const Geometry& g = q->scene->geometries_[args->geomID];
    if (g.kind != Geometry::Kind::Triangles) return false;  // spheres: below
    const uint32_t* index = &g.indices[3 * size_t(args->primID)];
    const float before = args->query->radius;
    const uint64_t id = (uint64_t(args->geomID) << 32) | uint64_t(args->primID);
    const float after =
        q->visitor->triangle(id, g.positions[index[0]], g.positions[index[1]], g.positions[index[2]], before);
    if (!(after < before)) return false;
    args->query->radius = std::max(after, 0.0f);
    return true;
  };
  rtcPointQuery(rtc_scene_, &query, &context, visit, &query_data);
  for (const Geometry& g : geometries_)
    if (g.kind == Geometry::Kind::Sphere) query.radius = std::min(query.radius, visitor.sphere(g.center, g.radius, query.radius));
}

const SurfaceBvh& Scene::surface_bvh() const {
  std::call_once(surface_bvh_built_, [this] {
    for (size_t id = 0; id < geometries_.size(); ++id) {
      const Geometry& g = geometries_[id];
      if (g.kind == Geometry::Kind::Sphere) {
        surface_bvh_.add_sphere(g.center, g.radius);
        continue;
      }
      surface_bvh_.add_mesh(uint32_t(id), g.positions, g.indices);
    }
    surface_bvh_.build();
  });
  return surface_bvh_;
}

const ClearanceField& Scene::clearance_field() const {
  std::call_once(clearance_field_built_, [this] { clearance_field_.build(surface_bvh()); });
  return clearance_field_;
}

}  // namespace emlt
