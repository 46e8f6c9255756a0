#include "mutations/ensemble/spread_scaled_perturbation.h"

#include <algorithm>
#include <cmath>

#include "mutations/ensemble/guide_spread.h"
#include "mutations/ensemble/guided_common.h"

namespace emlt {

SpreadScaledPerturbation::SpreadScaledPerturbation(std::string name,
                                                   std::unique_ptr<Mutation> inner)
    : name_(std::move(name)), inner_(std::move(inner)) {}

std::optional<Proposal> SpreadScaledPerturbation::propose(const Path& x, Rng& rng,
                                                          const MutationContext& ctx) const {
  const auto guides = ensemble::counter_guides_for(x, ctx);
  if (guides.size() < 2) return ensemble::unguided_step(*inner_, x, rng, ctx);
  const double spread = ensemble::guide_spread(guides.rasters());
  const Camera& camera = ctx.scene.camera();
  const double diagonal = std::hypot(double(camera.width()), double(camera.height()));
  MutationContext scaled = ctx;
  scaled.lens_max_radius = float(std::clamp(spread, 4.0 * double(ctx.lens_min_radius), diagonal));
  return inner_->propose(x, rng, scaled);
}

}  // namespace emlt
