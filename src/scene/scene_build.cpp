// Scene::build: a scene description checked, its meshes and spheres turned into Embree
// geometry with their materials, lights and alpha tests, and the light set assembled.
#include <fmt/format.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <mutex>
#include <string>

#include "emlt/core/error.h"
#include "emlt/scene/collimated_light.h"
#include "emlt/scene/cube_environment.h"  // complete for Scene's unique_ptr member
#include "emlt/scene/cube_map_environment.h"
#include "emlt/scene/directional_light.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/point_light.h"
#include "emlt/scene/scene.h"
#include "emlt/scene/shape_builders.h"
#include "emlt/scene/sphere_intersection.h"
#include "emlt/scene/texture.h"
#include "src/scene/parameter_ranges.h"
#include "src/scene/scene_geometry.h"

namespace emlt {

namespace {

// Lane i of an Embree ray packet of width n: its origin and direction.
std::pair<Vec3, Vec3> ray_lane(RTCRayN* ray, unsigned n, unsigned i) {
  return {Vec3(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i)),
          Vec3(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i))};
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
  if ((camera.crop_width != 0 || camera.crop_height != 0) &&
      !(camera.cropped() && camera.crop_x >= 0 && camera.crop_y >= 0 &&
        int64_t(camera.crop_x) + camera.crop_width <= camera.width &&
        int64_t(camera.crop_y) + camera.crop_height <= camera.height))
    throw file_error(desc.source, fmt::format("crop window {}x{} at ({}, {}) does not lie within "
                                              "the {}x{} film",
                                              camera.crop_width, camera.crop_height, camera.crop_x,
                                              camera.crop_y, camera.width, camera.height));
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
  // Mitsuba's `vertexcolors` on a surface without colours reads a colour nothing set (its
  // intersection record's, left from an earlier hit or never written): no image to match.
  auto warn_if_colorless = [&](int material, bool colorless, const std::string& shape) {
    if (colorless && material >= 0 && material < int(d.materials.size()) &&
        d.materials[size_t(material)].reads_vertex_colors)
      d.warnings.push_back(d.source + ": shape '" + shape +
                           "' has no vertex colours but its material reads them "
                           "(vertexcolors); they read black (Mitsuba reads an unset colour)");
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
    if (!mesh.colors.empty() && mesh.colors.size() != mesh.positions.size())
      throw file_error(d.source,
                       "mesh '" + mesh.name + "': colour count differs from vertex count");
    ++s.stats_.meshes;

    Geometry g;
    g.kind = Geometry::Kind::Triangles;
    g.name = mesh.name;
    assign_material(g, mesh.material, mesh.name);
    g.uvs = std::move(mesh.uvs);
    g.colors = std::move(mesh.colors);
    s.has_vertex_colors_ |= !g.colors.empty();
    warn_if_colorless(mesh.material, g.colors.empty(), mesh.name);
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
      Vec3 cross =
          glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
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
    warn_if_colorless(sphere.material, true, sphere.name);
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
    throw file_error(d.source,
                     skipped.empty()
                         ? std::string("scene has no geometry")
                         : "scene has no geometry: every shape was skipped (" + skipped + ")");
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
  } else if (env.kind == EnvironmentDesc::Kind::CubeMap) {
    if (!std::isfinite(env.scale) || env.scale < 0.0f || !is_finite_matrix(env.to_world))
      throw file_error(d.source, "environment map scale/transform must be finite (scale >= 0)");
    if (env.cube_faces.size() != size_t(CubeMapEnvironment::kFaces))
      throw file_error(d.source, "a cube map needs six faces");
    std::array<Image, CubeMapEnvironment::kFaces> faces;
    for (size_t f = 0; f < faces.size(); ++f) {
      faces[f] = env.cube_faces[f];
      if (faces[f].width <= 0 || faces[f].width != faces[f].height ||
          faces[f].width != faces[0].width)
        throw file_error(d.source, "a cube map's faces must be square and of one size");
    }
    if (env.scale > 0.0f)
      environment = std::make_unique<CubeMapEnvironment>(std::move(faces), env.scale,
                                                         Mat3(env.to_world));
  }
  if (environment) {
    environment->set_scene_bounds(s.bounds_center_, s.bounds_radius_);
    s.stats_.has_environment = true;
    lights.push_back(std::move(environment));
  }
  for (const PointLightDesc& point : d.point_lights) {
    const auto finite_ok = [](const Rgb& c) {
      return is_finite(c) && c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f;
    };
    if (!is_finite(point.position) || !finite_ok(point.intensity))
      throw file_error(d.source,
                       "a point light's position and intensity must be finite (intensity >= 0)");
    Frame frame;
    frame.s = glm::normalize(point.orientation[0]);
    frame.t = glm::normalize(point.orientation[1]);
    frame.n = glm::normalize(point.orientation[2]);
    std::optional<SpotProfile> spot;
    if (point.spot) spot = SpotProfile{point.cutoff, point.beam_width, point.texture};
    lights.push_back(std::make_unique<PointLight>(point.position, frame, point.intensity, spot,
                                                  options.delta_light_faults));
  }
  for (const DirectionalLightDesc& directional : d.directional_lights) {
    if (!is_finite(directional.direction) || !(glm::length(directional.direction) > 0.0f) ||
        !is_finite(directional.irradiance) ||
        std::min({directional.irradiance.x, directional.irradiance.y, directional.irradiance.z}) <
            0.0f)
      throw file_error(d.source,
                       "a directional light needs a direction and a finite irradiance >= 0");
    auto light = std::make_unique<DirectionalLight>(directional.direction, directional.irradiance);
    light->set_scene_bounds(s.bounds_center_, s.bounds_radius_);
    lights.push_back(std::move(light));
  }
  for (const CollimatedLightDesc& beam : d.collimated_lights) {
    if (!is_finite(beam.origin) || !is_finite(beam.direction) ||
        !(glm::length(beam.direction) > 0.0f) || !is_finite(beam.power) ||
        std::min({beam.power.x, beam.power.y, beam.power.z}) < 0.0f)
      throw file_error(d.source, "a collimated beam needs a finite origin, a direction and a power >= 0");
    lights.push_back(std::make_unique<CollimatedLight>(beam.origin, beam.direction, beam.power));
  }
  Rgb total_power(0.0f);
  for (const LightPtr& light : lights) total_power += light->power();
  if (lights.empty() || !(max_component(total_power) > 0.0f))
    throw file_error(d.source, "scene has no emitter (no emissive shape, light or environment)");
  s.lights_ = LightSet(std::move(lights));

  s.camera_ = std::make_unique<Camera>(d.camera, options.camera_faults);

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

}  // namespace emlt
