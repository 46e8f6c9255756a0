#pragma once
// Geometry-aware (GAMLT-like) lens, caustic and multi-chain perturbations (Otsu et al.
// 2018's idea, our own design).
// Each has the structure of Veach's perturbation of the same name (and reuses its
// deterministic move and Jacobians), but its step range depends on the path through the
// occluder-free cones of the segments whose visibility the move can break (cone.h):
//   lens:       image radius 1/r on [r1, R(x)],  R(x) = clamp(c · ρ(x), r_lo, r_hi), ρ the
//               pixel offset that keeps the connection x_l–x_{l+1} inside its cone (apex
//               x_l): α_conn · |x_{l+1} − x_l| / (rpp · L_eye), rpp the radians per pixel,
//               L_eye the eye subpath's length to x_{l+1}. The eye ray itself is traced, not
//               connected: an occluder beside it changes the surface it meets but cannot
//               block the move, so its cone is left out by default (eye_cone);
//   caustic:    angle 1/θ on [θ1, Θ(x)],  Θ(x) = clamp(c · min(α_first, α_eye · d_eye / L_chain),
//               θ_lo, θ_hi), with Veach's length-scaled θ1, θ2 (CausticPerturbation::angle_range);
//               here the eye segment is a connection, so its cone counts;
//   multichain: the lens radius above, and at each interior non-specular vertex i an angle
//               1/θ on [θ1, Θ_i(x)], Θ_i(x) = clamp(c · α_i, θ_lo, θ_hi), α_i the cone of the
//               segment the vertex turns (apex x_i, towards x_{i−1}).
// The clamps keep Veach's ranges as floor and ceiling: hi = ceiling · (Veach's largest
// step), lo = max(3 · Veach's smallest, floor · Veach's largest). The cone modulates the
// range between them.
//
// Why these defaults (c = 4, floor 0.5, ceiling 2). Measured on scenes/door-ajar (64 x 64,
// 256 mutations per pixel, relMSE against a 16384-spp BDPT image, mean of 6 seeds): plain
// MLT 9.6e-4; the first design (c = 0.5, no floor, ceiling 1, eye cone in the lens range)
// 2.0e-3 with acceptance 0.79 (ga-lens) / 0.80 (ga-caustic): the isotropic cone of a
// segment through the door gap is limited by the gap's nearest edge, while moves along the
// gap succeed, so ranges of half the cone were far smaller than the steps that pay. With
// c = 4 and the floor, 8.9e-4 (acceptance 0.55 / 0.61); c = 2: 9.0e-4; ceiling 3 or floor
// 0.25 (c = 8): 9.9e-4 and 1.0e-3. The seeds' spread is about 15 %, so none of these is
// resolvably better than plain MLT per mutation on this scene. The floor also bounds the
// cost: a cone below lo / c or above hi / c cannot change the range, so the estimate stops
// there (cone.h's alpha_min and alpha_max).
//
// Densities and acceptance. The 1/r offset on [r1, R] has planar density
// 1/(2π |Δ|² ln(R/r1)); the 1/θ direction on [θ1, Θ] has solid-angle density
// 1/(2π θ sin θ ln(Θ/θ1)). The reverse move y → x uses the same |Δ| and the same angles
// (both measured between x and y), but y's ranges R(y), Θ(y). Everything else (the Jacobians
// from the image plane/directions to area measure, the Dirac conventions) is Veach's and
// comes from the base move's retrace, which carries no range terms of its own. So
//     log T(y→x)/T(x→y) = (base) + log ln(R(x)/r1) − log ln(R(y)/r1)      (lens, multichain)
//                        + Σ_i [log ln(Θ_i(x)/θ1(x)) − log ln(Θ_i(y)/θ1(y))]  (caustic, multichain)
// and = −∞ when |Δ| > R(y) or some θ_i outside [θ1(y), Θ_i(y)]: the reverse move could not
// be proposed.
//
// The range terms at y need y's cones, the costly part of a step; they are what a proposal
// defers (Proposal::deferred, when ctx.may_defer: under delayed acceptance), and the driver
// asks deferred_log_ratio for them only once the first stage has passed. What the proposal
// keeps (the base move's ratio) is a ratio in its own right, as that stage needs.
//
// reverse_uses_x_cones = true is a deliberately wrong variant for the tests: the reverse
// density is evaluated with x's ranges, i.e. the correction above is dropped.
// stage_one_keeps_x_range = true is another (lens only): the whole ratio is unchanged, but
// x's normalisation log ln(R(x)/r1) moves into the part the proposal keeps, which is then
// no ratio in its own right (exchanging x and y does not invert it); invisible without
// delayed acceptance.
#include "mutations/caustic_perturbation.h"
#include "mutations/lens_perturbation.h"
#include "mutations/multichain_perturbation.h"

namespace emlt {

// Builds what the cone estimates search: the surface hierarchy, and the clearance field when
// ctx asks for the cheap cones.
void prepare_cones(const MutationContext& ctx);

struct GeometryAwareParams {
  double step_scale = 4.0;  // c: the largest step as a multiple of the free cone
  double ceiling = 2.0;     // upper clamp, as a multiple of Veach's largest step
  double floor = 0.5;       // lower clamp, as a fraction of Veach's largest step (at least 3 x the smallest)
  bool eye_cone = false;    // lens and multi-chain radius also limited by the eye ray's cone
  bool reverse_uses_x_cones = false;  // injected bug, tests only
  bool stage_one_keeps_x_range = false;  // injected bug, tests only
};

class GaLensPerturbation final : public Mutation {
 public:
  explicit GaLensPerturbation(GeometryAwareParams params = {}) : params_(params) {}
  std::string_view name() const override { return "ga-lens"; }
  void prepare(const MutationContext& ctx) const override { prepare_cones(ctx); }
  bool applies_to(const Path& x, const MutationContext& ctx) const override { return base_.applies_to(x, ctx); }
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;
  std::optional<Proposal> perturb_to(const Path& x, const Vec2& raster, const MutationContext& ctx) const;
  double deferred_log_ratio(const Path& x, const Proposal& proposal,
                            const MutationContext& ctx) const override;
  // R(z) in pixels.
  double max_radius(const Path& z, const MutationContext& ctx) const;

 private:
  // log ln(R(x)/r1) − log ln(R(y)/r1), or −∞ when y's range does not reach x.
  double reverse_range_term(const Path& x, double r_x, const Path& y,
                            const MutationContext& ctx) const;

  GeometryAwareParams params_;
  LensPerturbation base_;
};

class GaCausticPerturbation final : public Mutation {
 public:
  explicit GaCausticPerturbation(GeometryAwareParams params = {}) : params_(params) {}
  std::string_view name() const override { return "ga-caustic"; }
  void prepare(const MutationContext& ctx) const override { prepare_cones(ctx); }
  bool applies_to(const Path& x, const MutationContext& ctx) const override { return base_.applies_to(x, ctx); }
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;
  std::optional<Proposal> perturb_to(const Path& x, const Vec3& direction, const MutationContext& ctx) const;
  double deferred_log_ratio(const Path& x, const Proposal& proposal,
                            const MutationContext& ctx) const override;
  // θ1 and Θ(z) for path z.
  void angle_range(const Path& z, const MutationContext& ctx, double* theta_min, double* theta_max) const;

 private:
  // The angle between x's and y's first directions at the fixed vertex.
  double turn_angle(const Path& x, const Path& y) const;
  // log ln(Θ(x)/θ1(x)) − log ln(Θ(y)/θ1(y)), or −∞ when y's range does not hold θ.
  double reverse_range_term(double min_x, double max_x, double theta, const Path& y,
                            const MutationContext& ctx) const;

  GeometryAwareParams params_;
  CausticPerturbation base_;
};

class GaMultiChainPerturbation final : public Mutation {
 public:
  explicit GaMultiChainPerturbation(GeometryAwareParams params = {}) : params_(params) {}
  // Veach's angle range [θ1, θ2] other than MultiChainPerturbation's default (tests).
  GaMultiChainPerturbation(GeometryAwareParams params, double theta_min, double theta_max)
      : params_(params), base_(theta_min, theta_max) {}
  std::string_view name() const override { return "ga-multichain"; }
  void prepare(const MutationContext& ctx) const override { prepare_cones(ctx); }
  bool applies_to(const Path& x, const MutationContext& ctx) const override { return base_.applies_to(x, ctx); }
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;
  std::optional<Proposal> perturb_to(const Path& x, const Vec2& raster, const std::vector<Vec3>& directions,
                                     const MutationContext& ctx) const;
  double deferred_log_ratio(const Path& x, const Proposal& proposal,
                            const MutationContext& ctx) const override;
  // Θ_i(z) for the interior non-specular vertices, in order from the eye.
  std::vector<double> angle_limits(const Path& z, const MutationContext& ctx) const;
  // R(z) in pixels.
  double max_radius(const Path& z, const MutationContext& ctx) const;

 private:
  std::vector<double> turn_angles(const Path& x, const Path& y) const;
  // The image and angular range terms at x and y, or −∞ when y's ranges do not reach x.
  double reverse_range_term(const Path& x, double r_x, const std::vector<double>& limits_x,
                            const std::vector<double>& thetas, const Path& y,
                            const MutationContext& ctx) const;

  GeometryAwareParams params_;
  MultiChainPerturbation base_;
};

}  // namespace emlt
