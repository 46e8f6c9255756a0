#pragma once
// Veach's lens perturbation (1997 §11.4.3). It acts on paths
// whose eye end is (L|D) D S* E: the image point moves by a 1/r-distributed offset, the ray
// from the same lens point is traced through the same specular lobes to a new first
// non-specular vertex, and that vertex is connected to the fixed x_l. Small image-space
// steps on the paths that a lens subpath "owns" (everything seen directly or in mirrors and
// glass), cheap and with a high acceptance rate.
#include "emlt/mcmc/mutation.h"

namespace emlt {

class LensPerturbation final : public Mutation {
 public:
  // include_jacobian = false drops the area-measure Jacobian from the acceptance ratio (a
  // deliberately wrong strategy, for the tests that show a missing term is detected).
  explicit LensPerturbation(bool include_jacobian = true) : include_jacobian_(include_jacobian) {}

  std::string_view name() const override { return "lens"; }
  bool applies_to(const Path& x, const MutationContext& ctx) const override;
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;

  // The deterministic part: x moved so that it lands at `raster` (tests call it with the
  // raster of a previous proposal to run the reverse move).
  std::optional<Proposal> perturb_to(const Path& x, const Vec2& raster, const MutationContext& ctx) const;

  // Index l of the fixed light-side vertex x_l of a (L|D) D S* E suffix, or -1.
  static int fixed_vertex(const PathType& type);

 private:
  bool include_jacobian_;
};

}  // namespace emlt
