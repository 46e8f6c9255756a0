#include "emlt/scene/scene.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <mutex>
#include <string>

#include "emlt/core/error.h"
#include "emlt/scene/cube_environment.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/shape_builders.h"
#include "emlt/scene/sphere_intersection.h"
#include "emlt/scene/texture.h"
#include "src/scene/parameter_ranges.h"
#include "src/scene/scene_geometry.h"

namespace emlt {

Rgb SurfaceHit::emitted(const Vec3& w) const {
  return light ? light->emitted(geometric_normal, w) : Rgb(0.0f);
}

namespace {
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

}  // namespace

bool Scene::Geometry::lets_through(const Vec3& origin, const Vec3& direction, float t,
                                   uint32_t geometry_id, uint32_t primitive, float b1,
                                   float b2) const {
  const Vec2 uv = uv_at(primitive, b1, b2, origin + t * direction);
  const float alpha = luminance(colors.empty() ? opacity->eval(uv)
                                               : opacity->eval_at(uv, color_at(primitive, b1, b2)));
  if (alpha >= 1.0f) return false;
  return !(alpha > 0.0f) ||
         alpha_test_threshold(origin, direction, geometry_id, primitive) >= alpha;
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
    hit.vertex_color = Rgb(0.0f);
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
    hit.vertex_color = g.color_at(hit.primitive_id, u, v);
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

const CubeEnvironment* Scene::cube_environment(int resolution) const {
  if (!environment()) return nullptr;
  std::call_once(cube_environment_built_, [this, resolution] {
    cube_environment_ = std::make_unique<CubeEnvironment>(*environment(), resolution);
  });
  return cube_environment_.get();
}

}  // namespace emlt
