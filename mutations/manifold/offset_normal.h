#pragma once
// Offset manifolds (Jakob & Marschner 2012, §5.3): a rough vertex the manifold perturbation
// treats as specular keeps its microfacet normal m fixed in a local frame at the surface, so
// that it reflects or refracts like a mirror about m while the path moves. The local frame
// must be a function of the surface point alone (not of the path): the reverse move reads
// the offset back from y's own geometry, and only a frame that depends on the position
// gives it the offset the forward move used. The frame here is the shading normal n with a
// tangent made from the world axis least aligned with n (piecewise constant in n), so that
// its derivative follows from n's alone (Scene::shading_normal_derivative).
//
// The offset's measure: m = F(p) o turns o rigidly, so a density per unit solid angle of o
// is one per unit solid angle of m, and the move, which keeps o, moves the outgoing
// direction with |dω_out/dm| (half_vector_jacobian) per unit of m's solid angle.
#include "emlt/core/math.h"

namespace emlt::manifold {

struct OffsetFrame {
  DVec3 s{0.0}, t{0.0}, n{0.0};

  explicit OffsetFrame(const DVec3& normal) : n(normal) {
    const DVec3 e = reference_axis(n);
    const DVec3 u = e - n * glm::dot(n, e);
    s = glm::normalize(u);
    t = glm::cross(n, s);
  }
  DVec3 to_local(const DVec3& w) const { return {glm::dot(w, s), glm::dot(w, t), glm::dot(w, n)}; }
  DVec3 to_world(const DVec3& o) const { return o.x * s + o.y * t + o.z * n; }

  // d(F o) for a change dn of the normal (the axis stays: it is piecewise constant).
  DVec3 differential(const DVec3& o, const DVec3& dn) const {
    const DVec3 e = reference_axis(n);
    const DVec3 u = e - n * glm::dot(n, e);
    const double length = glm::length(u);
    const DVec3 du = -dn * glm::dot(n, e) - n * glm::dot(dn, e);
    const DVec3 ds = (du - s * glm::dot(s, du)) / length;
    const DVec3 dt = glm::cross(dn, s) + glm::cross(n, ds);
    return o.x * ds + o.y * dt + o.z * dn;
  }

  static DVec3 reference_axis(const DVec3& n) {
    const DVec3 a = glm::abs(n);
    if (a.x <= a.y && a.x <= a.z) return {1.0, 0.0, 0.0};
    return a.y <= a.z ? DVec3(0.0, 1.0, 0.0) : DVec3(0.0, 0.0, 1.0);
  }
};

// The microfacet normal that scatters the direction towards `back` (unit, pointing away
// from the vertex, on the side with index eta_back) into `out` (unit, away, index eta_out):
// the generalized half vector, turned to the side of `normal`. Reflection: eta_back ==
// eta_out. Zero when the directions admit none.
inline DVec3 microfacet_normal(const DVec3& back, const DVec3& out, double eta_back, double eta_out,
                               const DVec3& normal) {
  DVec3 m = eta_back * back + eta_out * out;
  const double length = glm::length(m);
  if (!(length > 0.0)) return DVec3(0.0);
  m /= length;
  return glm::dot(m, normal) < 0.0 ? -m : m;
}

// The direction leaving a vertex reached along `d` (unit, the direction of travel) when it
// reflects about m (r = 0) or refracts with r = eta_in / eta_out (r > 0): Snell's law about
// m. Nothing for total internal reflection.
inline bool scatter_about(const DVec3& d, const DVec3& m, bool refract, double r, DVec3* out) {
  const double a = glm::dot(d, m);
  if (!refract) {
    *out = d - 2.0 * a * m;
    return true;
  }
  const double b2 = 1.0 - r * r * (1.0 - a * a);
  if (!(b2 > 0.0)) return false;
  const double b = a < 0.0 ? -std::sqrt(b2) : std::sqrt(b2);
  *out = glm::normalize(r * d + (b - r * a) * m);
  return true;
}

// |dω_out/dm| at a vertex that scatters `back` into `out` about m (both unit and pointing
// away): 4 |out.m| for reflection; for refraction the inverse of Walter et al.'s (2007)
// |dm/dω_out| = eta_out^2 |out.m| / (eta_back back.m + eta_out out.m)^2.
inline double half_vector_jacobian(const DVec3& back, const DVec3& out, const DVec3& m,
                                   bool refract, double eta_back, double eta_out) {
  const double out_m = std::abs(glm::dot(out, m));
  if (!refract) return 4.0 * out_m;
  const double sum = eta_back * glm::dot(back, m) + eta_out * glm::dot(out, m);
  return out_m > 0.0 ? sum * sum / (eta_out * eta_out * out_m) : 0.0;
}

}  // namespace emlt::manifold
