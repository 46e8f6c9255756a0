#pragma once
// The mutation interface every MCMC strategy implements (mutations/*.cpp). A strategy
// proposes y from x and reports the log of its proposal-density ratio T(y->x) / T(x->y);
// the driver owns everything else: selection among strategies (whose probabilities enter
// the ratio when applicability differs between x and y), the scalar target
// f*(x) = luminance of the path contribution, acceptance and splatting.
//
// Strategies hold no mutable state, so chains run in parallel without locks. Anything a
// strategy needs besides the path comes through the MutationContext.
#include <limits>
#include <optional>
#include <string_view>

#include "emlt/core/rng.h"
#include "emlt/path/path.h"

namespace emlt {

class EnsembleGuides;

struct MutationContext {
  const Scene& scene;
  int min_edges = 1;   // shortest path the chains may visit (3 when direct light is separate)
  int max_edges = 30;  // longest (max_depth, or the unlimited cap)
  // Image-plane perturbation radii in pixels (Veach: 0.1 px and 5 % of the image area).
  float lens_min_radius = 0.1f;
  float lens_max_radius = 0.0f;
  // The manifold perturbation's step factor λ (mutations/manifold_perturbation.h; Mitsuba's
  // probFactor): its direction lobe's peak is λ² times the start vertex's own density.
  double manifold_prob_factor = 50.0;
  // Its offset manifolds' typical change of a microfacet normal per move, in radians (Mitsuba's
  // avgAngleChangeSurface, whose starting guess of 1 degree this is); 0: rough vertices always
  // end walks and chains.
  double manifold_angle_change = 0.017453292519943295;
  // EMLT (ensemble_guides.h): the frozen complementary ensemble, and the key of the current
  // step (the chain and how many steps it has taken) that fixes Υ. Null outside EMLT; the
  // guided strategies then behave as their unguided fallbacks.
  const EnsembleGuides* ensemble = nullptr;
  uint64_t chain = 0, step = 0;
  // The geometry-aware perturbations' occluder-free cones by the cheap conservative bound
  // instead of the exact hierarchy walk (mutations/geometry_aware/cone.h; --gamlt-cone).
  bool field_cone = false;
  // > 0: the cones memoised by quantised segments, cells of this fraction of the segment's
  // length (mutations/geometry_aware/cone_cells.h; --gamlt-cone cells, --gamlt-cone-cell).
  double cone_cell_fraction = 0.0;
  // The caller asks Mutation::deferred_log_ratio for what a proposal marked `deferred` leaves
  // out (the MLT driver under delayed acceptance, --gamlt-acceptance delayed); without it
  // every proposal carries its whole ratio.
  bool may_defer = false;
};

struct Proposal {
  Path path;
  // log T(y->x) - log T(x->y) of this strategy alone (selection probability excluded).
  double log_reverse_over_forward = 0.0;
  // Part of the ratio is left out, for Mutation::deferred_log_ratio (only when ctx.may_defer):
  // a factor costly to evaluate (the geometry-aware strategies' ranges at y, which need y's
  // cones) that a proposal rejected by the first stage of delayed acceptance (f(y) = 0
  // included) never needs. What stays must be a ratio in its own right: exchanging x and y
  // inverts f(y)/f(x) · exp(log_reverse_over_forward), which the first stage's detailed balance
  // needs (include/emlt/mcmc/delayed_acceptance.h).
  bool deferred = false;
  // A guided strategy that used its unguided fallback (fewer than two guides), for the stats.
  bool fallback = false;
  // The stretch scale α a guided linear kernel drew with (EMLT §3.4), for the statistics;
  // negative when the step drew none.
  double alpha = -1.0;
};

// The whole log ratio from a proposal's first part and its deferred one: -infinity whenever
// the deferred part is (the reverse move impossible), whatever the first part.
inline double with_deferred(double first, double deferred) {
  return deferred == -std::numeric_limits<double>::infinity() ? deferred : first + deferred;
}

class Mutation {
 public:
  virtual ~Mutation() = default;
  virtual std::string_view name() const = 0;
  // Whether this strategy can act on x at all (by its path type); evaluated on both x and
  // the proposal, since it fixes the selection probability in each direction.
  virtual bool applies_to(const Path& x, const MutationContext& ctx) const = 0;
  // A proposal, or nothing when sampling failed (treated as a rejection).
  virtual std::optional<Proposal> propose(const Path& x, Rng& rng,
                                          const MutationContext& ctx) const = 0;
  // Builds what the strategy searches in the scene besides its rays (once per scene, kept
  // by the scene), before the chains start, so that no chain's step pays for it; ctx is the
  // one the chains will use.
  virtual void prepare(const MutationContext& /*ctx*/) const {}
  // The log-ratio factor a proposal left out (Proposal::deferred), from x and that proposal:
  // log T(y->x) - log T(x->y) is with_deferred(proposal.log_reverse_over_forward, this),
  // -infinity when y could not propose x.
  virtual double deferred_log_ratio(const Path& /*x*/, const Proposal& /*proposal*/,
                                    const MutationContext& /*ctx*/) const {
    return 0.0;
  }
};

}  // namespace emlt
