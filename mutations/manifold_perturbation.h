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
// Rough surfaces are treated as non-specular (Mitsuba's offset manifolds for them are not
// implemented): chains are made of Dirac interactions only.
#include <vector>

#include "emlt/mcmc/mutation.h"

namespace emlt {

class ManifoldPerturbation final : public Mutation {
 public:
  // Mistakes injected for the tests that must catch them.
  struct Faults {
    bool drop_generalized_geometry = false;  // the chain's |dω/dA| left out of the ratio
    bool accept_unconverged = false;         // a walk that did not converge used anyway
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
  // The von Mises-Fisher concentration κ whose density at its mode is `peak`, and the log
  // density at cos θ from the mode (κ = 0: uniform over the sphere).
  static double concentration_for_peak(double peak);
  static double log_vmf_density(double kappa, double cos_theta);

 private:
  Faults faults_;
};

}  // namespace emlt
