#pragma once
// The manifold perturbation of Jakob & Marschner's manifold exploration (2012, §5), as
// Mitsuba 0.6's MEMLT runs it: a non-specular vertex x_a is chosen with a direction along
// the path (towards the eye or the light); the direction leaving x_a is turned by a von
// Mises-Fisher step and traced through the Dirac vertices that followed it to a new
// non-specular vertex x_b; the Dirac chain from x_b to the next non-specular vertex x_c,
// which stays where it is, is then re-solved by the manifold walk (manifold/specular_chain.h)
// so that it joins the moved x_b to the fixed x_c. Paths that reach a small light only
// through a specular chain (a caustic seen through water from a point light) can then be
// moved at all: no other perturbation can reconnect across a Dirac chain.
//
// Step size (Mitsuba's rule): the von Mises-Fisher lobe about the old direction has peak
// value λ² · max(1/4π, p(ω)), p(ω) the solid-angle density with which x_a itself would
// sample that direction (its BSDF, the light's emission or the camera's ray density), so the
// step is narrow where x_a's own scattering is, about a pixel at the lens. λ is
// ctx.manifold_prob_factor (--manifold-prob-factor; Mitsuba's probFactor, default 50).
//
// Start choice: the moves (a, direction) allowed by the path type, the one from the lens
// with probability 1/4 when there are others (Mitsuba's preference for the sensor), the rest
// uniformly; the choice depends on the path type alone, which y shares, so it cancels.
//
// Rough surfaces (offset manifolds, the paper's §5.3, as Mitsuba runs them): where the move
// would end its walk (x_b) or its chain (x_c) at a rough vertex, it passes through it instead
// as if it were specular with probability 1 - nonspecular_probability, reflecting or
// refracting about x's microfacet normal kept fixed in a frame of the surface
// (manifold/offset_normal.h); the walk's Jacobian gains |dω_out/dm| there, the chain's
// generalized geometry term is that of the offset manifold, and the ratio carries the
// chance of the same choice from y. ctx.manifold_angle_change = 0 turns them off.
#include <vector>

#include "emlt/mcmc/mutation.h"
#include "mutations/manifold/specular_chain.h"

namespace emlt {

class ManifoldPerturbation final : public Mutation {
 public:
  // Mistakes injected for the tests that must catch them.
  struct Faults {
    bool drop_generalized_geometry = false;  // the chain's |dω/dA| left out of the ratio
    bool accept_unconverged = false;         // a walk that did not converge used anyway
    bool drop_half_vector_jacobian = false;  // rough vertices' |dω_out/dm| left out
  };
  ManifoldPerturbation() = default;
  explicit ManifoldPerturbation(Faults faults) : faults_(faults) {}

  std::string_view name() const override { return "manifold"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override;
  std::optional<Proposal> propose(const Path& x, Rng& rng,
                                  const MutationContext& ctx) const override;

  // One move: turn at x_a, trace along `step` (+1 towards the eye, -1 towards the light) to
  // x_b, re-solve the chain from x_b to the fixed x_c.
  struct Move {
    int a = 0, b = 0, c = 0, step = 0;
  };
  // The moves x's type allows (the same for every path of that type).
  static std::vector<Move> moves(const Path& x);
  // The deterministic part: x with the direction leaving x_a replaced by `direction`, and
  // the whole ratio (the von Mises-Fisher densities included).
  std::optional<Proposal> perturb_to(const Path& x, const Move& move, const Vec3& direction,
                                     const MutationContext& ctx) const;

  // A direction leaving x_a drawn from the move's von Mises-Fisher lobe about x's own (u
  // uniform on the unit square); nothing where x_a's own density is zero.
  static std::optional<Vec3> sample_direction(const Path& x, const Move& move,
                                              const MutationContext& ctx, const Vec2& u);
  // The solid-angle density with which x_a samples the direction towards x_{a+step}.
  static double direction_density(const Path& path, int a, int step);
  // The probability that a rough vertex ends a walk or a chain instead of being crossed as
  // specular (Mitsuba's nonspecularProb): for each non-Dirac component of roughness alpha,
  // (1 - cos θ) / (1 - cos(θ + Δ)), θ = atan(-ln(1 - 0.9) alpha²) the angle holding 90 % of a
  // Beckmann lobe's normals and Δ the typical change of the microfacet normal a move makes
  // (--manifold-angle-change); averaged over the components; 1 for diffuse ones, 0 at Dirac
  // vertices.
  static double nonspecular_probability(double alpha, double angle_change);
  static double nonspecular_probability(const PathVertex& v, const MutationContext& ctx);
  // log of the chance that the move's walk from x_a ends at x_b and its chain at x_c, given
  // a and the direction.
  static double log_chain_choice(const Path& path, const Move& move, const MutationContext& ctx);

  // The chain from x_c to x_b the walk solves for, with x's own links (the rough ones with
  // x's microfacet normals) and x's x_b as its target; nothing where a rough link has none.
  static std::optional<manifold::ChainProblem> chain_problem(const Scene& scene, const Path& x,
                                                             const Move& move);
  // log of the area of the chain's vertices per unit solid angle of their microfacet normals
  // (rough links) with x_b and x_c held: the measure the move's ratio gives x's chain. The
  // walk's area conversions from x_c with |dω_out/dm| at each rough link, times
  // |dω_c/dA(x_b)|. Zero-dimensional Dirac links contribute their conversions only.
  std::optional<double> log_chain_measure(const Scene& scene, const Path& x,
                                          const Move& move) const;

  // The von Mises-Fisher concentration κ whose density at its mode is `peak`, and the log
  // density at cos θ from the mode (κ = 0: uniform over the sphere).
  static double concentration_for_peak(double peak);
  static double log_vmf_density(double kappa, double cos_theta);

 private:
  Faults faults_;
};

}  // namespace emlt
