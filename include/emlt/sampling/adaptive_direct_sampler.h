#pragma once
// `--direct-sampler adaptive`: Szécsi, Szirmay-Kalos, Kurt and Csébfalvi's adaptive sampling
// for environment mapping (seed 001, section 4). The directions arriving at a shading point
// are parametrised over the unit square (the diffuse BRDF's map, Eq. 6, or the global
// spherical one, Eq. 5), and the integral of F = L_in f_s cos (dw/du) over the square is
// computed by the Halton-cell refinement of halton_cells.h, each cell's split decided by
// the derivative of the visibility-free integrand L_env f_s cos (dw/du) at its point.
//
// The estimate is deterministic given the first Halton index (drawn per shading point, the
// paper's "random initial index") and, because the cells depend on the values found, biased
// (consistent): it is refused where an unbiased direct estimate is required.
#include <array>
#include <vector>

#include "emlt/core/frame.h"
#include "emlt/core/rng.h"
#include "emlt/sampling/halton_cells.h"
#include "emlt/scene/scene.h"
#include "emlt/settings/settings.h"

namespace emlt {

// The map from the unit square to directions (world) and its Jacobian dw / (du_1 du_2).
//   Global (section 4.1): phi = 2 pi u_1, theta = pi u_2 about the world's +y axis,
//     dw/du = 2 pi^2 sin(pi u_2), the whole sphere.
//   Cosine (section 4.2, Eq. 6): w = T cos(2 pi u_1) sqrt(u_2) + B sin(2 pi u_1) sqrt(u_2)
//     + N sqrt(1 - u_2) in `frame`, dw/du = pi / sqrt(1 - u_2), the hemisphere about N.
class AdaptiveDirectionMap {
 public:
  AdaptiveDirectionMap(AdaptiveParametrisation parametrisation, const Frame& frame)
      : parametrisation_(parametrisation), frame_(frame) {}
  Vec3 direction(const std::array<double, 2>& u) const;
  double jacobian(const std::array<double, 2>& u) const;

 private:
  AdaptiveParametrisation parametrisation_;
  Frame frame_;
};

struct AdaptiveDirectOptions {
  int budget = 2;  // directions (rays) per estimate
  int initial = 1;
  double robustness = 1.0;
  AdaptiveParametrisation parametrisation = AdaptiveParametrisation::Cosine;
};

// What one estimate did, for tests and figures: the final cells, and at each cell's point
// the direction and F.
struct AdaptiveDirectTrace {
  std::vector<AdaptiveLeaf> leaves;
  std::vector<Vec3> directions;
  std::vector<Rgb> values;
};

// The adaptive estimate of the direct light reflected at `hit` towards wo (world, unit):
// environment and area lights as the rays find them (area lights' edges, like visibility,
// are left out of the derivative, section 3.3), delta lights added exactly (one shadow ray
// each: no direction finds them). A BSDF with a delta lobe, which no parametrisation can
// find, and one that transmits under the cosine map, are handled as the caller says: this
// estimates only what `parametrisation` covers, and estimate_direct_lighting sends such
// BSDFs elsewhere (direct_lighting.cpp).
Rgb estimate_direct_adaptive(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, Rng& rng,
                             const AdaptiveDirectOptions& options,
                             AdaptiveDirectTrace* trace = nullptr);

}  // namespace emlt
