#pragma once
// Veach's multi-chain perturbation (1997 §11.4.3) for paths whose
// eye end is (L|D) D (S+ D)+ S* E: a non-specular vertex seen through specular chains that
// are separated by further non-specular vertices (a caustic lit indirectly, seen through
// glass...), where the lens perturbation cannot connect. The image point moves as in the
// lens perturbation; at every interior non-specular vertex met on the way to the light the
// old outgoing direction is turned by a 1/θ-distributed angle; the walk stops at the first
// pair of adjacent non-specular vertices (x_l, x_{l+1}) and connects them.
//
// Angle range: fixed, θ ∈ [1e-4, 0.1] rad (Veach & Guibas 1997's caustic values), the same
// for every path, so the angular density is symmetric and cancels (the length-scaled
// caustic heuristic would make it path-dependent, and Mitsuba's 0.0001°..0.1° are so small
// that the move hardly leaves the pixel). Configurable through the constructor.
#include "emlt/mcmc/mutation.h"

namespace emlt {

class MultiChainPerturbation final : public Mutation {
 public:
  // walks_to_light: also move paths whose eye walk ends on the light (walks_to_light(x));
  // off, Veach's form alone.
  explicit MultiChainPerturbation(double theta_min = 1e-4, double theta_max = 0.1,
                                  bool include_jacobian = true, bool walks_to_light = true)
      : theta_min_(theta_min),
        theta_max_(theta_max),
        include_jacobian_(include_jacobian),
        walks_to_light_(walks_to_light) {}

  std::string_view name() const override { return "multichain"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override;
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;

  // The deterministic part: image point `raster`; at each interior non-specular vertex, in
  // order from the eye, the next of `directions` (world, leaving towards the light).
  std::optional<Proposal> perturb_to(const Path& x, const Vec2& raster, const std::vector<Vec3>& directions,
                                     const MutationContext& ctx) const;
  // The same without the angular steps' range check: the ratio holds the Jacobians and the
  // convention correction only, for a caller whose image-plane and direction densities are
  // its own (EMLT's guided multi-chain perturbation).
  std::optional<Proposal> retrace(const Path& x, const Vec2& raster, const std::vector<Vec3>& directions,
                                  const MutationContext& ctx) const;

  // Index l of the fixed vertex of a (L|D) D (S+ D)+ S* E suffix, or -1.
  static int fixed_vertex(const PathType& type);
  // Whether x has the form L S+ (D S+)* S* E with x_0 on an emitting surface: no two adjacent
  // non-specular vertices, so the eye walk's last chain ends on the light itself (the floor
  // under water lit through the water and seen through it, a lamp seen through glass). The
  // walk then traces on to the light (which must again be hit) instead of connecting;
  // Mitsuba's multi-chain perturbation moves such paths the same way, and no other of
  // Veach's perturbations applies to them.
  static bool walks_to_light(const Path& x);
  // Where the walk ends: fixed_vertex's l, -1 for a walk to the light, kNotApplicable.
  static constexpr int kNotApplicable = -2;
  int walk_end(const Path& x) const;

  double theta_min() const { return theta_min_; }
  double theta_max() const { return theta_max_; }

 private:
  double theta_min_, theta_max_;
  bool include_jacobian_;
  bool walks_to_light_;
};

}  // namespace emlt
