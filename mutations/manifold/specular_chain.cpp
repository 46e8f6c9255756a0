#include "mutations/manifold/specular_chain.h"

#include "mutations/manifold/offset_normal.h"
#include "mutations/perturbation_common.h"

namespace emlt::manifold {
namespace {

// A right-handed orthonormal pair perpendicular to unit w (any fixed rule will do: the
// walk only needs the same pair for the same ω).
void perpendicular_pair(const DVec3& w, DVec3* s, DVec3* t) {
  const DVec3 helper = std::abs(w.x) < 0.9 ? DVec3(1.0, 0.0, 0.0) : DVec3(0.0, 1.0, 0.0);
  *s = glm::normalize(glm::cross(helper, w));
  *t = glm::cross(w, *s);
}

// A ray from p along d that starts on the line through p itself: the usual offset along
// the normal (spawn_ray) shifts that line sideways by up to 1e-4 of the scene's scale,
// which a curved chain magnifies into a visible miss of the point it was solved for. The
// surface p lies on is skipped by the same distance along the ray instead.
Ray ray_leaving(const Vec3& p, const Vec3& d) {
  const float skip =
      1e-4f * glm::max(1.0f, glm::max(std::abs(p.x), glm::max(std::abs(p.y), std::abs(p.z))));
  return Ray{p, d, skip, kInfinity};
}

// Moves a position differential dp (on one plane, along direction d) over distance t to
// the plane with normal n: dp + t dd, then along d back onto the plane.
DVec3 transfer(const DVec3& dp, const DVec3& dd, double t, const DVec3& d, const DVec3& n,
               double d_dot_n) {
  const DVec3 moved = dp + t * dd;
  return moved - (glm::dot(moved, n) / d_dot_n) * d;
}

}  // namespace

bool trace_chain(const ChainProblem& problem, const DVec3& direction, ChainTrace* trace) {
  const Scene& scene = *problem.scene;
  const DVec3 w = glm::normalize(direction);
  if (!std::isfinite(w.x + w.y + w.z)) return false;
  DVec3 axis[2];
  perpendicular_pair(w, &axis[0], &axis[1]);
  // The ray's point p and direction d, and their derivatives with respect to turning ω
  // about axis[0] and axis[1].
  DVec3 p(problem.start.position), d = w;
  DVec3 dp[2] = {DVec3(0.0), DVec3(0.0)}, dd[2] = {axis[0], axis[1]};
  trace->direction = w;
  trace->links.clear();
  Ray ray = problem.start.is_surface() ? ray_leaving(problem.start.position, Vec3(w))
                                       : Ray{problem.start.position, Vec3(w), 0.0f, kInfinity};
  for (const ChainLink& link : problem.links) {
    SurfaceHit hit;
    if (!scene.intersect(ray, hit) || hit.bsdf != link.bsdf || hit.bsdf->is_anisotropic())
      return false;
    DMat3 dn_dp;
    if (!scene.shading_normal_derivative(hit, &dn_dp)) return false;
    const DVec3 q(hit.position), ng(hit.geometric_normal);
    const double t = glm::dot(q - p, d), d_dot_ng = glm::dot(d, ng);
    if (!(t > 0.0) || !(std::abs(d_dot_ng) > 1e-12)) return false;
    for (int j = 0; j < 2; ++j) dp[j] = transfer(dp[j], dd[j], t, d, ng, d_dot_ng);
    p = q;

    const PathVertex vertex = make_surface_vertex(hit);
    const DVec3 n(hit.shading_normal);
    // The normal the link scatters about (the shading normal, or a rough link's microfacet
    // normal) and its derivatives; the direction leaving and r = n_in / n_out.
    DVec3 m = n, dm[2] = {dn_dp * dp[0], dn_dp * dp[1]}, d_out;
    double r = 1.0;
    if (link.rough) {
      const OffsetFrame frame(n);
      m = frame.to_world(link.offset);
      for (int j = 0; j < 2; ++j) dm[j] = frame.differential(link.offset, dm[j]);
      if (link.transmission) r = glm::dot(d, n) < 0.0 ? 1.0 / link.ior : link.ior;
      if (!scatter_about(d, m, link.transmission, r, &d_out)) return false;
      // The lobe must leave on its own side of the surface: back for a reflection, through
      // for a refraction.
      const double arrival = glm::dot(d, ng), departure = glm::dot(d_out, ng);
      if (link.transmission ? arrival * departure <= 0.0 : arrival * departure >= 0.0)
        return false;
    } else {
      float eta = 1.0f;
      const auto next = perturbation::continue_through_delta(vertex, Vec3(-d), problem.mode,
                                                             link.transmission, &eta);
      if (!next) return false;
      d_out = glm::normalize(DVec3(*next));
      if (link.transmission) r = 1.0 / double(eta);
    }
    // The outgoing direction as a function of d and m: a reflection d - 2 (d.m) m, or a
    // refraction r d + (b - r a) m with a = d.m, b = d_out.m, b^2 = 1 - r^2 (1 - a^2);
    // differentiated with dm from the normal's derivative dn = W dp.
    const double a = glm::dot(d, m), b = glm::dot(d_out, m);
    if (link.transmission && !(std::abs(b) > 1e-12)) return false;
    for (int j = 0; j < 2; ++j) {
      const double da = glm::dot(dd[j], m) + glm::dot(d, dm[j]);
      dd[j] = link.transmission ? r * dd[j] + (b - r * a) * dm[j] + (r * r * a / b - r) * da * m
                                : dd[j] - 2.0 * da * m - 2.0 * a * dm[j];
    }
    d = d_out;
    trace->links.push_back(vertex);
    ray = ray_leaving(hit.position, Vec3(d));
  }

  const DVec3& nq = problem.target_normal;
  const double d_dot_nq = glm::dot(d, nq);
  if (!(std::abs(d_dot_nq) > 1e-12)) return false;
  const double t = glm::dot(problem.target - p, nq) / d_dot_nq;
  if (!(t > 0.0)) return false;
  trace->end = p + t * d;
  DVec3 plane[2];
  perpendicular_pair(nq, &plane[0], &plane[1]);
  for (int j = 0; j < 2; ++j) {
    const DVec3 de = transfer(dp[j], dd[j], t, d, nq, d_dot_nq);
    trace->jacobian[0][j] = glm::dot(de, plane[0]);
    trace->jacobian[1][j] = glm::dot(de, plane[1]);
  }
  const DVec3 offset = trace->end - problem.target;
  trace->offset[0] = glm::dot(offset, plane[0]);
  trace->offset[1] = glm::dot(offset, plane[1]);
  trace->residual = glm::length(offset);
  return std::isfinite(trace->residual) && std::isfinite(trace->area_per_solid_angle());
}

std::optional<ChainTrace> solve_chain(const ChainProblem& problem, const DVec3& guess,
                                      double tolerance, bool accept_unconverged) {
  ChainTrace current;
  if (!trace_chain(problem, guess, &current)) return std::nullopt;
  double step = 1.0;
  for (int i = 0; i < kMaxNewtonSteps && !(current.residual < tolerance); ++i) {
    const auto& J = current.jacobian;
    const double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    if (!(std::abs(det) > 0.0) || !std::isfinite(det)) break;
    // The Newton step that would bring the end onto the target: -J^-1 offset.
    const double turn0 = -(J[1][1] * current.offset[0] - J[0][1] * current.offset[1]) / det;
    const double turn1 = -(J[0][0] * current.offset[1] - J[1][0] * current.offset[0]) / det;
    DVec3 axis0, axis1;
    perpendicular_pair(current.direction, &axis0, &axis1);
    const DVec3 candidate = current.direction + step * (turn0 * axis0 + turn1 * axis1);
    ChainTrace next;
    if (trace_chain(problem, candidate, &next) && next.residual < current.residual) {
      current = std::move(next);
      step = std::min(1.0, 2.0 * step);
    } else {
      step *= 0.5;
    }
  }
  if (current.residual < tolerance || accept_unconverged) return current;
  return std::nullopt;
}

}  // namespace emlt::manifold
