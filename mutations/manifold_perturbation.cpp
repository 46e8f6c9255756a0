#include "mutations/manifold_perturbation.h"

#include <cmath>

#include "emlt/path/connection.h"
#include "mutations/manifold/offset_normal.h"
#include "mutations/manifold/specular_chain.h"
#include "mutations/perturbation_common.h"

namespace emlt {

// Acceptance ratio. The move keeps everything but x_{a+step} .. x_{c-step} (and the lens
// point's raster when a or c is the lens). Its free variable is the direction ω leaving x_a:
// the traced vertices x_{a+step} .. x_b follow from ω, and the chain between x_b and the
// fixed x_c from x_b. In the path layer's reference measure ν (perturbation_common.h) the
// vertices a walk from x_a reaches through Dirac lobes have dν = dω / K_ab, K_ab the walk's
// area conversions without its lobe probabilities (as for the caustic perturbation), and a
// Dirac chain walked from x_c to x_b has dν = dω_c / K_cb. With x_c fixed, ω_c is a function
// of x_b: dω_c = D dA(x_b), D = |dω_c/dA(x_b)| the chain's generalized geometry term over
// the end cosines (Jakob & Marschner §4.3), which the walk's Jacobian gives. The measure of
// the moved vertices given the fixed ones is therefore dω · D / (K_ab K_cb), and
//     T(x -> y) = p(ω_y | x) K_ab(y) K_cb(y) / D(y),
//     log T(y->x)/T(x->y) = log p(ω_x|y) - log p(ω_y|x)
//                           + log(K_ab K_cb / D)(x) - log(K_ab K_cb / D)(y),
// with p the von Mises-Fisher lobe (its concentration set at each path by its own start
// density, so the two lobes differ). Without a chain (c = b + step), K_cb = D = cos/d² and
// the chain terms vanish. x's D comes from the reverse walk, which must find x's chain
// again (otherwise y could not propose x and the move is refused, as Mitsuba does). Dirac
// values are rewritten in the walks' modes and x's converted (log_convention_correction).
namespace {

// Where a walk may turn or a chain may end: a non-specular point with a position.
bool fixed_point(const PathVertex& v) {
  return !v.delta && !v.is_environment() && v.kind != VertexKind::OrthographicCamera;
}

// How a rough vertex i of `path` scatters when the move treats it as specular: its
// microfacet normal in the local frame (the same whichever way the walk crosses it), whether
// it refracts, and the material's interior/exterior index.
struct RoughScatter {
  DVec3 offset{0.0, 0.0, 1.0}, normal{0.0};  // m in the local frame and in the world
  bool refract = false;
  double ior = 1.0;
  double eta_prev = 1.0, eta_next = 1.0;  // the indices on the sides of i - 1 and i + 1
};

std::optional<RoughScatter> rough_scatter(const Path& path, int i) {
  const auto& v = path.vertices;
  const PathVertex &z = v[size_t(i)], &prev = v[size_t(i - 1)], &next = v[size_t(i + 1)];
  RoughScatter r;
  r.refract = perturbation::crosses_surface(z, next, prev);
  const DVec3 n(z.shading.n);
  const DVec3 to_prev = perturbation::precise_direction(z, prev),
              to_next = perturbation::precise_direction(z, next);
  if (r.refract) {
    r.ior = z.bsdf->rough_components(BsdfContext{z.uv, TransportMode::Radiance, z.vertex_color}).eta;
    r.eta_prev = glm::dot(to_prev, n) > 0.0 ? 1.0 : r.ior;
    r.eta_next = glm::dot(to_next, n) > 0.0 ? 1.0 : r.ior;
  }
  r.normal = manifold::microfacet_normal(to_prev, to_next, r.eta_prev, r.eta_next, n);
  if (!(glm::dot(r.normal, r.normal) > 0.0)) return std::nullopt;
  r.offset = manifold::OffsetFrame(n).to_local(r.normal);
  return r;
}

// log K of the vertices from + step .. to, walked from `from` (perturbation_common.h's
// log_light_jacobian and log_eye_jacobian in either direction). A rough vertex the walk
// crossed as specular about its microfacet normal m spreads the walk by |dω_out/dm|: the
// area of the vertex after it per unit solid angle of m is d²/cos times that.
double log_walk_jacobian(const Path& path, int from, int to, int step,
                         const ManifoldPerturbation::Faults& faults) {
  const auto& v = path.vertices;
  double log_jacobian = 0.0;
  for (int i = from + step;; i += step) {
    const PathVertex &z = v[size_t(i)], &before = v[size_t(i - step)];
    const double stored = step > 0 ? double(z.pdf_from_light) : double(z.pdf_from_eye);
    const double factor = i == from + step || !before.delta
                              ? double(solid_angle_to_vertex_measure(1.0f, before, z))
                              : stored / double(before.delta_probability);
    log_jacobian += std::log(factor);
    if (i != from + step && !before.delta && !faults.drop_half_vector_jacobian) {
      const auto rough = rough_scatter(path, i - step);
      if (!rough) return std::numeric_limits<double>::quiet_NaN();
      const DVec3 back = perturbation::precise_direction(before, v[size_t(i - 2 * step)]);
      const DVec3 out = perturbation::precise_direction(before, z);
      const double eta_back = step > 0 ? rough->eta_prev : rough->eta_next;
      const double eta_out = step > 0 ? rough->eta_next : rough->eta_prev;
      log_jacobian -= std::log(manifold::half_vector_jacobian(back, out, rough->normal,
                                                              rough->refract, eta_back, eta_out));
    }
    if (i == to) break;
  }
  return log_jacobian;
}

double chain_length(const Path& path, int from, int to) {
  double length = 0.0;
  const int step = to > from ? 1 : -1;
  for (int i = from; i != to; i += step)
    length += glm::length(DVec3(path.vertices[size_t(i + step)].position) -
                          DVec3(path.vertices[size_t(i)].position));
  return length;
}

// The walk must end this close to its target, relative to the chain's length (the float
// geometry's hits resolve about 1e-7 of it).
constexpr double kRelativeTolerance = 1e-5;
// The reverse walk must find each of x's links this close (Mitsuba's relative 1e-3).
constexpr double kReversibilityTolerance = 1e-3;

Vec3 sample_vmf(const DVec3& mode, double kappa, const Vec2& u) {
  const double cos_theta =
      kappa > 1e-6
          ? std::clamp(1.0 + std::log1p(double(u.x) * std::expm1(-2.0 * kappa)) / kappa, -1.0, 1.0)
          : 1.0 - 2.0 * double(u.x);
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * M_PI * double(u.y);
  const DVec3 helper = std::abs(mode.x) < 0.9 ? DVec3(1.0, 0.0, 0.0) : DVec3(0.0, 1.0, 0.0);
  const DVec3 s = glm::normalize(glm::cross(helper, mode)), t = glm::cross(mode, s);
  return Vec3(
      glm::normalize(cos_theta * mode + sin_theta * (std::cos(phi) * s + std::sin(phi) * t)));
}

}  // namespace

double ManifoldPerturbation::nonspecular_probability(double alpha, double angle_change) {
  if (!(alpha < std::numeric_limits<double>::infinity()) || !(angle_change > 0.0)) return 1.0;
  // The microfacet normals' spread: the angle within which a Beckmann lobe of roughness alpha
  // holds the quantile q of its normals (Mitsuba's MTS_MANIFOLD_QUANTILE_SURFACE, 0.9).
  constexpr double kQuantile = 0.9;
  const double theta_domain = std::atan(-std::log(1.0 - kQuantile) * alpha * alpha);
  if (!(theta_domain > 0.0)) return 0.0;
  return (1.0 - std::cos(theta_domain)) / (1.0 - std::cos(theta_domain + angle_change));
}

double ManifoldPerturbation::nonspecular_probability(const PathVertex& v,
                                                     const MutationContext& ctx) {
  if (v.delta) return 0.0;
  if (!v.is_surface() || !v.bsdf) return 1.0;
  const RoughComponents rough =
      v.bsdf->rough_components(BsdfContext{v.uv, TransportMode::Radiance, v.vertex_color});
  if (rough.count == 0) return 1.0;
  double sum = 0.0;
  for (int i = 0; i < rough.count; ++i)
    sum += nonspecular_probability(double(rough.alpha[i]), ctx.manifold_angle_change);
  return sum / double(rough.count);
}

double ManifoldPerturbation::log_chain_choice(const Path& path, const Move& move,
                                              const MutationContext& ctx) {
  const auto& v = path.vertices;
  double log_probability = 0.0;
  for (int i = move.a + move.step; i != move.c; i += move.step) {
    if (v[size_t(i)].delta) continue;
    const double p = nonspecular_probability(v[size_t(i)], ctx);
    log_probability += std::log(i == move.b ? p : 1.0 - p);
  }
  // An end of the path ends the chain with no draw.
  if (move.c > 0 && move.c < path.edges())
    log_probability += std::log(nonspecular_probability(v[size_t(move.c)], ctx));
  return log_probability;
}

double ManifoldPerturbation::concentration_for_peak(double peak) {
  // The density at the mode is κ / (2π (1 - e^{-2κ})), at least 1/4π (κ -> 0).
  const double target = 2.0 * M_PI * peak;
  if (!(target > 0.5 + 1e-9)) return 0.0;
  // Newton on g(κ) = κ - target (1 - e^{-2κ}), convex, from the right of its root.
  double kappa = target;
  for (int i = 0; i < 50; ++i) {
    const double e = std::exp(-2.0 * kappa);
    const double next = kappa - (kappa - target * (1.0 - e)) / (1.0 - 2.0 * target * e);
    if (!(next > 0.0)) break;
    const bool settled = std::abs(next - kappa) <= 1e-14 * kappa;
    kappa = next;
    if (settled) break;
  }
  return kappa;
}

double ManifoldPerturbation::log_vmf_density(double kappa, double cos_theta) {
  if (!(kappa > 1e-6)) return -std::log(4.0 * M_PI);
  return std::log(kappa) + kappa * (cos_theta - 1.0) - std::log(2.0 * M_PI) -
         std::log(-std::expm1(-2.0 * kappa));
}

double ManifoldPerturbation::direction_density(const Path& path, int a, int step) {
  const auto& v = path.vertices;
  const PathVertex &from = v[size_t(a)], &to = v[size_t(a + step)];
  const double stored = step > 0 ? double(to.pdf_from_light) : double(to.pdf_from_eye);
  const double conversion = double(solid_angle_to_vertex_measure(1.0f, from, to));
  return conversion > 0.0 ? stored / conversion : 0.0;
}

namespace {

// Calls visit(move) for each move x's type allows, in a fixed order, until it returns true;
// no allocation, so that applies_to, asked on every step, stays cheap.
template <typename Visit>
bool visit_moves(const Path& x, Visit visit) {
  const auto& v = x.vertices;
  const int k = x.edges();
  for (int a = 0; a <= k; ++a) {
    if (!fixed_point(v[size_t(a)])) continue;
    for (const int step : {-1, 1}) {
      int b = a + step;
      while (b >= 0 && b <= k && v[size_t(b)].delta) b += step;
      if (b <= 0 || b >= k || !v[size_t(b)].is_surface()) continue;
      int c = b + step;
      while (c >= 0 && c <= k && v[size_t(c)].delta) c += step;
      if (c < 0 || c > k || !fixed_point(v[size_t(c)])) continue;
      if (visit(ManifoldPerturbation::Move{a, b, c, step})) return true;
    }
  }
  return false;
}

}  // namespace

std::vector<ManifoldPerturbation::Move> ManifoldPerturbation::moves(const Path& x) {
  std::vector<Move> found;
  visit_moves(x, [&](const Move& m) {
    found.push_back(m);
    return false;
  });
  return found;
}

bool ManifoldPerturbation::applies_to(const Path& x, const MutationContext&) const {
  return visit_moves(x, [](const Move&) { return true; });
}

std::optional<Proposal> ManifoldPerturbation::propose(const Path& x, Rng& rng,
                                                      const MutationContext& ctx) const {
  const std::vector<Move> options = moves(x);
  if (options.empty()) return std::nullopt;
  const int k = x.edges();
  const auto from_lens =
      std::find_if(options.begin(), options.end(), [k](const Move& m) { return m.a == k; });
  const float u = rng.uniform();
  Move move;
  if (from_lens != options.end() && (options.size() == 1 || u < 0.25f)) {
    move = *from_lens;
  } else {
    // The others uniformly (u rescaled onto them when the lens move had its quarter).
    std::vector<Move> others;
    for (const Move& m : options)
      if (m.a != k) others.push_back(m);
    const float v = from_lens != options.end() ? (u - 0.25f) / 0.75f : u;
    move = others[std::min(others.size() - 1, size_t(v * float(others.size())))];
  }
  // Offset manifolds: a rough vertex met where the move would end its walk or its chain is
  // passed through as specular with probability 1 - nonspecular_probability (no draw for
  // vertices that always or never end them, so scenes without such vertices see the same
  // random numbers as without offset manifolds).
  const auto extend = [&](int from) {
    for (int i = from;; i += move.step) {
      if (i <= 0 || i >= k) return i;
      const PathVertex& z = x.vertices[size_t(i)];
      if (z.delta) continue;
      const double p = nonspecular_probability(z, ctx);
      if (p >= 1.0 || double(rng.uniform()) < p) return i;
    }
  };
  move.b = extend(move.a + move.step);
  if (move.b <= 0 || move.b >= k || !x.vertices[size_t(move.b)].is_surface()) return std::nullopt;
  move.c = extend(move.b + move.step);
  if (move.c < 0 || move.c > k || !fixed_point(x.vertices[size_t(move.c)])) return std::nullopt;
  const auto direction = sample_direction(x, move, ctx, rng.uniform2());
  if (!direction) return std::nullopt;
  return perturb_to(x, move, *direction, ctx);
}

std::optional<Vec3> ManifoldPerturbation::sample_direction(const Path& x, const Move& move,
                                                           const MutationContext& ctx,
                                                           const Vec2& u) {
  const double density = direction_density(x, move.a, move.step);
  if (!(density > 0.0)) return std::nullopt;
  const double lambda = ctx.manifold_prob_factor;
  const double kappa =
      concentration_for_peak(lambda * lambda * std::max(1.0 / (4.0 * M_PI), density));
  const DVec3 old_direction = perturbation::precise_direction(
      x.vertices[size_t(move.a)], x.vertices[size_t(move.a + move.step)]);
  return sample_vmf(old_direction, kappa, u);
}

std::optional<manifold::ChainProblem> ManifoldPerturbation::chain_problem(const Scene& scene,
                                                                         const Path& x,
                                                                         const Move& move) {
  const auto& xv = x.vertices;
  manifold::ChainProblem problem;
  problem.scene = &scene;
  problem.start = xv[size_t(move.c)];
  problem.mode = move.step > 0 ? TransportMode::Radiance : TransportMode::Importance;
  for (int i = move.c - move.step; i != move.b; i -= move.step) {
    manifold::ChainLink link{
        xv[size_t(i)].bsdf,
        perturbation::crosses_surface(xv[size_t(i)], xv[size_t(i + 1)], xv[size_t(i - 1)])};
    if (!xv[size_t(i)].delta) {
      const auto rough = rough_scatter(x, i);
      if (!rough) return std::nullopt;
      link.rough = true;
      link.offset = rough->offset;
      link.ior = rough->ior;
    }
    problem.links.push_back(link);
  }
  problem.target = DVec3(xv[size_t(move.b)].position);
  problem.target_normal = DVec3(xv[size_t(move.b)].normal);
  return problem;
}

std::optional<double> ManifoldPerturbation::log_chain_measure(const Scene& scene, const Path& x,
                                                              const Move& move) const {
  const auto problem = chain_problem(scene, x, move);
  if (!problem) return std::nullopt;
  manifold::ChainTrace trace;
  const DVec3 w = perturbation::precise_direction(x.vertices[size_t(move.c)],
                                                  x.vertices[size_t(move.c - move.step)]);
  if (!manifold::trace_chain(*problem, w, &trace) || !(trace.area_per_solid_angle() > 0.0))
    return std::nullopt;
  return -log_walk_jacobian(x, move.c, move.b, -move.step, faults_) -
         std::log(trace.area_per_solid_angle());
}

std::optional<Proposal> ManifoldPerturbation::perturb_to(const Path& x, const Move& move,
                                                         const Vec3& direction,
                                                         const MutationContext& ctx) const {
  const Scene& scene = ctx.scene;
  const int k = x.edges();
  const int a = move.a, b = move.b, c = move.c, step = move.step;
  const auto& xv = x.vertices;
  Proposal proposal;
  Path& y = proposal.path;
  y = x;
  auto& yv = y.vertices;
  const auto crosses = [&xv](int i) {
    return perturbation::crosses_surface(xv[size_t(i)], xv[size_t(i + 1)], xv[size_t(i - 1)]);
  };

  // 1. From x_a along the new direction through the same lobes to the new x_b.
  const TransportMode walk_mode = step > 0 ? TransportMode::Importance : TransportMode::Radiance;
  const PathVertex& start = xv[size_t(a)];
  Ray ray = start.is_surface() ? spawn_ray(start.position, start.normal, direction)
                               : Ray{start.position, direction, 0.0f, kInfinity};
  for (int i = a + step;; i += step) {
    auto hit = perturbation::trace_surface(scene, ray);
    if (!hit || hit->bsdf != xv[size_t(i)].bsdf) return std::nullopt;
    hit->throughput = xv[size_t(i)].throughput;
    yv[size_t(i)] = *hit;
    if (i == b) break;
    std::optional<Vec3> next;
    if (xv[size_t(i)].delta) {
      next = perturbation::continue_through_delta(
          yv[size_t(i)], direction_between(yv[size_t(i)], yv[size_t(i - step)]), walk_mode,
          crosses(i));
    } else {
      // A rough vertex crossed as specular: about x's microfacet normal, kept in the frame.
      const auto rough = rough_scatter(x, i);
      if (!rough) return std::nullopt;
      const DVec3 n(yv[size_t(i)].shading.n);
      const DVec3 m = manifold::OffsetFrame(n).to_world(rough->offset);
      const DVec3 d = -perturbation::precise_direction(yv[size_t(i)], yv[size_t(i - step)]);
      const double r = glm::dot(d, n) < 0.0 ? 1.0 / rough->ior : rough->ior;
      DVec3 out;
      if (!manifold::scatter_about(d, m, rough->refract, r, &out)) return std::nullopt;
      const DVec3 ng(yv[size_t(i)].normal);
      const double arrival = glm::dot(d, ng), departure = glm::dot(out, ng);
      if (rough->refract ? arrival * departure <= 0.0 : arrival * departure >= 0.0)
        return std::nullopt;
      next = Vec3(out);
    }
    if (!next) return std::nullopt;
    ray = spawn_ray(yv[size_t(i)].position, yv[size_t(i)].normal, *next);
  }
  for (int i = a + step; i != b; i += step)
    if (xv[size_t(i)].delta && !perturbation::fill_delta_record(yv[size_t(i)], yv[size_t(i + 1)], yv[size_t(i - 1)],
                                         walk_mode, crosses(i)))
      return std::nullopt;

  // 2. The chain from the fixed x_c to the moved x_b, and back to x's x_b.
  const TransportMode chain_mode = step > 0 ? TransportMode::Radiance : TransportMode::Importance;
  double log_chain_x = 0.0, log_chain_y = 0.0;  // -log D of each path's chain
  if (std::abs(c - b) > 1) {
    auto chain = chain_problem(scene, x, move);
    if (!chain) return std::nullopt;
    manifold::ChainProblem& problem = *chain;
    const double length = chain_length(x, c, b);
    // The walk from the fixed x_c, started along `from`'s chain, to `to`'s x_b.
    const auto walk = [&](const Path& from, const Path& to) {
      problem.target = DVec3(to.vertices[size_t(b)].position);
      problem.target_normal = DVec3(to.vertices[size_t(b)].normal);
      return manifold::solve_chain(problem,
                                   perturbation::precise_direction(from.vertices[size_t(c)],
                                                                   from.vertices[size_t(c - step)]),
                                   kRelativeTolerance * length, faults_.accept_unconverged);
    };
    const auto forward = walk(x, y);
    if (!forward) return std::nullopt;
    for (size_t j = 0; j < forward->links.size(); ++j) {
      const int i = c - step * int(j + 1);
      yv[size_t(i)] = forward->links[j];
      yv[size_t(i)].throughput = xv[size_t(i)].throughput;
    }
    // The reverse move: the walk from y's chain to x's x_b must find x's chain.
    const auto reverse = walk(y, x);
    if (!reverse) return std::nullopt;
    for (size_t j = 0; j < reverse->links.size(); ++j) {
      const int i = c - step * int(j + 1);
      if (glm::length(DVec3(reverse->links[j].position) - DVec3(xv[size_t(i)].position)) >
          kReversibilityTolerance * length)
        return std::nullopt;
    }
    for (int i = c - step; i != b; i -= step)
        if (xv[size_t(i)].delta &&
          !perturbation::fill_delta_record(yv[size_t(i)], yv[size_t(i + 1)], yv[size_t(i - 1)],
                                           chain_mode, crosses(i)))
        return std::nullopt;
    if (!mutually_visible(scene, yv[size_t(b + step)], yv[size_t(b)])) return std::nullopt;
    // D = |dω_c / dA(x_b)| = 1 / |dA/dω| of each path's own chain.
    const double area_y = forward->area_per_solid_angle(), area_x = reverse->area_per_solid_angle();
    if (!(area_x > 0.0) || !(area_y > 0.0)) return std::nullopt;
    if (!faults_.drop_generalized_geometry) {
      log_chain_x = std::log(area_x);  // - log D(x)
      log_chain_y = std::log(area_y);
    }
  } else if (!mutually_visible(scene, yv[size_t(b)], yv[size_t(c)])) {
    return std::nullopt;
  }

  // The lens point stays; where it sees its neighbour (its raster) moves with it.
  if ((a == k || c == k) && !perturbation::aim_lens_at(scene, yv[size_t(k)], yv[size_t(k - 1)]))
    return std::nullopt;
  const int low = std::min(a, c), high = std::max(a, c);
  if (!perturbation::finish_proposal(scene, x, y, low + 1, high == k ? k : high - 1))
    return std::nullopt;
  if (!(path_luminance(scene, y) > 0.0)) return std::nullopt;

  // 3. The ratio.
  const double lambda2 = ctx.manifold_prob_factor * ctx.manifold_prob_factor;
  const double density_x = direction_density(x, a, step), density_y = direction_density(y, a, step);
  if (!(density_x > 0.0) || !(density_y > 0.0)) return std::nullopt;
  const double kappa_x = concentration_for_peak(lambda2 * std::max(1.0 / (4.0 * M_PI), density_x));
  const double kappa_y = concentration_for_peak(lambda2 * std::max(1.0 / (4.0 * M_PI), density_y));
  const double cos_theta =
      glm::dot(perturbation::precise_direction(xv[size_t(a)], xv[size_t(a + step)]),
               perturbation::precise_direction(yv[size_t(a)], yv[size_t(a + step)]));
  double log_ratio = log_vmf_density(kappa_y, cos_theta) - log_vmf_density(kappa_x, cos_theta);
  log_ratio += log_walk_jacobian(x, a, b, step, faults_) - log_walk_jacobian(y, a, b, step, faults_);
  if (std::abs(c - b) > 1)  // K_cb, from the densities finish_proposal recomputed
    log_ratio += log_walk_jacobian(x, c, b, -step, faults_) -
                 log_walk_jacobian(y, c, b, -step, faults_);
  log_ratio += log_chain_x - log_chain_y;
  // The chance of the same walk and chain ends from y, against from x (they differ where
  // the rough vertices' roughness is textured).
  log_ratio += log_chain_choice(y, move, ctx) - log_chain_choice(x, move, ctx);
  const int first_turn = std::min(a, b) + 1, last_turn = std::max(a, b) - 1;
  if (first_turn <= last_turn)
    log_ratio -= perturbation::log_convention_correction(x, first_turn, last_turn, walk_mode);
  const int first_link = std::min(b, c) + 1, last_link = std::max(b, c) - 1;
  if (first_link <= last_link)
    log_ratio -= perturbation::log_convention_correction(x, first_link, last_link, chain_mode);
  if (std::isnan(log_ratio)) return std::nullopt;
  proposal.log_reverse_over_forward = log_ratio;
  return proposal;
}

}  // namespace emlt
