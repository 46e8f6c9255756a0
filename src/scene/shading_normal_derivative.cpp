#include "emlt/scene/scene.h"
#include "scene_geometry.h"

namespace emlt {

bool Scene::shading_normal_derivative(const SurfaceHit& hit, DMat3* dn_dp) const {
  if (hit.geometry_id >= geometries_.size()) return false;
  const Geometry& g = geometries_[hit.geometry_id];
  if (g.bump) return false;
  const DVec3 n(hit.shading_normal);
  const DMat3 projector = DMat3(1.0) - glm::outerProduct(n, n);
  if (g.kind == Geometry::Kind::Sphere) {
    // N = (P - centre) / r, flipped for an inward-facing sphere.
    *dn_dp = projector * ((g.flip_normals ? -1.0 : 1.0) / double(g.radius));
    return true;
  }
  if (g.normals.empty()) {
    *dn_dp = DMat3(0.0);
    return true;
  }
  const uint32_t* tri = &g.indices[3 * size_t(hit.primitive_id)];
  const DVec3 p0(g.positions[tri[0]]), p1(g.positions[tri[1]]), p2(g.positions[tri[2]]);
  const DVec3 e1 = p1 - p0, e2 = p2 - p0, area_normal = glm::cross(e1, e2);
  const double area_squared = glm::dot(area_normal, area_normal);
  if (!(area_squared > 0.0)) return false;
  // P - p0 = b1 e1 + b2 e2 on the triangle's plane, so b1 and b2 are affine in P with
  // gradients (e2 x A)/|A|^2 and (A x e1)/|A|^2 (A = e1 x e2), and b0 = 1 - b1 - b2.
  const DVec3 grad1 = glm::cross(e2, area_normal) / area_squared;
  const DVec3 grad2 = glm::cross(area_normal, e1) / area_squared;
  const DVec3 grad0 = -grad1 - grad2;
  const DVec3 d = DVec3(hit.position) - p0;
  const double b1 = glm::dot(d, grad1), b2 = glm::dot(d, grad2), b0 = 1.0 - b1 - b2;
  const DVec3 n0(g.normals[tri[0]]), n1(g.normals[tri[1]]), n2(g.normals[tri[2]]);
  const DVec3 m = b0 * n0 + b1 * n1 + b2 * n2;  // the unnormalised interpolated normal
  const double length = glm::length(m);
  if (!(length > 1e-12)) return false;
  const DMat3 dm_dp =
      glm::outerProduct(n0, grad0) + glm::outerProduct(n1, grad1) + glm::outerProduct(n2, grad2);
  // The hit's normal is m/|m| or its opposite (turned to the geometric side); the map
  // follows the same sign.
  const double sign = glm::dot(m, n) < 0.0 ? -1.0 : 1.0;
  *dn_dp = projector * dm_dp * (sign / length);
  return true;
}

}  // namespace emlt
