#pragma once
// Geometry-aware (GAMLT-like) lens, caustic and multi-chain perturbations (project issue 7;
// Otsu et al. 2018's idea as summarised in notes/mlt-algorithms.md §9, our own design).
// Each has the structure of Veach's perturbation of the same name (and reuses its
// deterministic move and Jacobians), but its step range depends on the path through the
// occluder-free cones of the segments the move turns (cone.h):
//   lens:       image radius 1/r on [r1, R(x)],  R(x) = clamp(c · ρ(x), r_lo, r2), with ρ the
//               pixel offset that keeps the eye ray and the connection x_l–x_{l+1} inside
//               their cones: min(α_eye / rpp, α_conn · |x_{l+1} − x_l| / (rpp · L_eye)),
//               rpp the radians per pixel, L_eye the eye subpath's length to x_{l+1};
//   caustic:    angle 1/θ on [θ1, Θ(x)],  Θ(x) = clamp(c · min(α_first, α_eye · d_eye / L_chain),
//               θ_lo, θ2) with Veach's θ1, θ2 (CausticPerturbation::angle_range);
//   multichain: the lens radius above, and at each interior non-specular vertex i an angle
//               1/θ on [θ1, Θ_i(x)], Θ_i(x) = clamp(c · α_i, θ_lo, θ2), α_i the cone of the
//               segment the vertex turns (apex x_i, towards x_{i−1}).
// r_lo = min(r2, 3 r1), θ_lo = min(θ2, 3 θ1): the range never collapses (ergodicity).
//
// Densities and acceptance. The 1/r offset on [r1, R] has planar density
// 1/(2π |Δ|² ln(R/r1)); the 1/θ direction on [θ1, Θ] has solid-angle density
// 1/(2π θ sin θ ln(Θ/θ1)). The reverse move y → x uses the same |Δ| and the same angles
// (both measured between x and y), but y's ranges R(y), Θ(y). Everything else (the Jacobians
// from the image plane/directions to area measure, the Dirac conventions) is Veach's and
// comes from the base move's log ratio. So, relative to a fixed-range perturbation,
//     log T(y→x)/T(x→y) += log ln(R(x)/r1) − log ln(R(y)/r1)          (lens, multichain)
//                        + Σ_i [log ln(Θ_i(x)/θ1) − log ln(Θ_i(y)/θ1)]  (caustic, multichain)
// and = −∞ when |Δ| ≥ R(y) or some θ_i ≥ Θ_i(y): the reverse move could not be proposed.
// (The caustic base move already holds Veach's path-dependent ln term, which is replaced.)
//
// reverse_uses_x_cones = true is a deliberately wrong variant for the tests: the reverse
// density is evaluated with x's ranges, i.e. the correction above is dropped.
#include "mutations/caustic_perturbation.h"
#include "mutations/lens_perturbation.h"
#include "mutations/multichain_perturbation.h"

namespace emlt {

struct GeometryAwareParams {
  double step_scale = 0.5;  // c: the fraction of the free cone a step may use
  bool reverse_uses_x_cones = false;  // injected bug, tests only
};

class GaLensPerturbation final : public Mutation {
 public:
  explicit GaLensPerturbation(GeometryAwareParams params = {}) : params_(params) {}
  std::string_view name() const override { return "ga-lens"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override { return base_.applies_to(x, ctx); }
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;
  std::optional<Proposal> perturb_to(const Path& x, const Vec2& raster, const MutationContext& ctx) const;
  // R(z) in pixels.
  double max_radius(const Path& z, const MutationContext& ctx) const;

 private:
  GeometryAwareParams params_;
  LensPerturbation base_;
};

class GaCausticPerturbation final : public Mutation {
 public:
  explicit GaCausticPerturbation(GeometryAwareParams params = {}) : params_(params) {}
  std::string_view name() const override { return "ga-caustic"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override { return base_.applies_to(x, ctx); }
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;
  std::optional<Proposal> perturb_to(const Path& x, const Vec3& direction, const MutationContext& ctx) const;
  // θ1 and Θ(z) for path z.
  void angle_range(const Path& z, const MutationContext& ctx, double* theta_min, double* theta_max) const;

 private:
  GeometryAwareParams params_;
  CausticPerturbation base_;
};

class GaMultiChainPerturbation final : public Mutation {
 public:
  explicit GaMultiChainPerturbation(GeometryAwareParams params = {}) : params_(params) {}
  std::string_view name() const override { return "ga-multichain"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override { return base_.applies_to(x, ctx); }
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;
  std::optional<Proposal> perturb_to(const Path& x, const Vec2& raster, const std::vector<Vec3>& directions,
                                     const MutationContext& ctx) const;
  // Θ_i(z) for the interior non-specular vertices, in order from the eye.
  std::vector<double> angle_limits(const Path& z, const MutationContext& ctx) const;

 private:
  GeometryAwareParams params_;
  MultiChainPerturbation base_;
};

}  // namespace emlt
