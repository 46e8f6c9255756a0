#pragma once
// EMLT's anisotropic path perturbation (Bashford-Rogers et al. 2021, §3.3, Fig. 10): the
// first two non-specular vertices from the camera, x_a = x_{k-1} and x_b = x_{k-2}, move by
// the guided anisotropic kernel (kernels.h, eqs. 11-12), in one of two orders picked at
// random (the paper's "from or toward the camera"):
//  - from the camera: the image point moves by an anisotropic Gaussian fitted to the guides'
//    image points (weighted by the similarity of their x_a, eq. 11) and the eye ray gives
//    y_a; then y_b is sampled on the tangent plane at x_b from a Gaussian fitted to the
//    guides' x_b (weighted by x_b and the fixed x_c = x_{k-3}), ray-cast from y_a, and
//    connected to x_c;
//  - toward the camera: y_b from the same Gaussian at x_b, ray-cast from x_c; then y_a from
//    a Gaussian on the tangent plane at x_a (weighted by x_a and the centre path's own x_b),
//    ray-cast from y_b; y_a is connected to the fixed lens point, which gives the new pixel.
// x_c may be the emitter vertex (L D D E paths).
//
// Densities are per unit area of the moved vertices, every Gaussian refitted at the point it
// is centred on for the reverse move (Σ from y's weights and tangent planes). From the camera:
//   T(x->y) = N_x(u_y) W H pdf_eye(y_a) * K_{x_b}(y_b | cast from y_a),
// toward the camera:
//   T(x->y) = K_{x_b}(y_b | cast from x_c) * K_{x_a}(y_a | cast from y_b),
// and the reverse of each with x and y exchanged.
//
// A cast that runs along the Gaussian's plane (the origin lands on that plane, e.g. y_a on
// x_b's face) has no density the kernel can evaluate: such moves are refused, and their
// reverse reported impossible (kernels.h). Accepting them with an infinite ratio was the
// 3-10 % bias that earlier sessions saw on these paths (tests/statistical/emlt_test.cpp).
// With fewer than two guides of x's type the step is Veach's lens perturbation.
#include "mutations/ensemble/guided_common.h"
#include "mutations/lens_perturbation.h"

namespace emlt {

struct AnisotropicPathParams {
  // World-space kernel at x_b; lengths are fractions of the scene's bounding radius. The
  // scales multiply the reliability-weighted covariances (--ensemble-aniso-covariance
  // weighted; eq. 11 as printed, the default, takes no factor): 0.05 measured best of
  // 0.01 / 0.05 / 0.25 / 1 on the Cornell box (MSE of emlt-ani 3.1 / 3.3 / 3.8 / 4.7e-4 at
  // 64 mutations per pixel, 64 x 64; acceptance 0.66 / 0.49 / 0.29 / 0.15).
  double covariance_scale = 0.05;
  double floor_fraction = 1e-4;
  // The fallback when a fit is unusable (a third of them on the Cornell box): the paper's vMF
  // about the direction from the cast origin to the current vertex, "with a high
  // concentration" (value not given); 1e4 is about 0.6 degrees wide. MSE at 64 mutations per
  // pixel, 64 x 64, seeds 1-8: emlt-ani 2.09e-4 (Cornell box) and 1.27e-4 (door); the full
  // mix at alpha = 1 2.01e-4 and 7.8e-5. On the door scene kappa from 3e3 to 1e5 gave 7.8e-5
  // to 8.4e-5 (full mix) and 1.25e-4 to 1.27e-4 (emlt-ani), the seeds' spread. The isotropic
  // plane Gaussian below (fallback_concentration = 0) measured 5-10 % lower on emlt-ani
  // (1.99e-4, 1.15e-4) and 0-6 % lower on the full mix (2.01e-4, 7.4e-5).
  double fallback_concentration = 1e4;
  // With fallback_concentration = 0, the paper's other option: an isotropic Gaussian on the
  // tangent plane, this fraction of the scene's radius wide.
  double fallback_fraction = 0.01;
  // Kish effective number of guides below which a fit falls back (kernels.h).
  double min_effective_guides = 2.0;
  // Image-plane kernel; lengths in pixels.
  double image_covariance_scale = 0.05;
  double image_floor_sigma = 0.1;
  double image_fallback_sigma = 2.0;
  // Probability of the toward-camera variant (the paper picks either at random).
  double toward_camera_probability = 0.5;
  // Shortest path (in segments) the strategy applies to; 3 lets x_c be the emitter vertex.
  int min_edges = 3;
};

class AnisotropicPathPerturbation final : public Mutation {
 public:
  explicit AnisotropicPathPerturbation(AnisotropicPathParams params = {},
                                       ensemble::InjectedBugs bugs = {})
      : params_(params), bugs_(bugs) {}
  std::string_view name() const override { return "emlt-aniso"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override;
  std::optional<Proposal> propose(const Path& x, Rng& rng,
                                  const MutationContext& ctx) const override;

 private:
  std::optional<Proposal> from_camera(const Path& x, const GuideView& guides, Rng& rng,
                                      const MutationContext& ctx) const;
  std::optional<Proposal> toward_camera(const Path& x, const GuideView& guides, Rng& rng,
                                        const MutationContext& ctx) const;

  AnisotropicPathParams params_;
  ensemble::InjectedBugs bugs_;
  LensPerturbation fallback_;
};

}  // namespace emlt
