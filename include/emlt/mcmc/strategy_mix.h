#pragma once
// The set of mutation strategies a chain draws from, with their weights
// (`--mutations bidir=3,lens=2,...`). A step picks among the strategies that apply to the
// current path in proportion to their weights, so the probability of picking strategy j
// depends on the path: P(j | x) = w_j [j applies to x] / sum_i w_i [i applies to x]. The
// acceptance ratio includes P(j | y) / P(j | x).
//
// A strategy may instead hold a fixed share of all proposals, written as a fraction
// (`bidir=1/3`): it is picked with that probability whenever it applies, and the weighted
// strategies that apply share the rest in proportion to their weights. (Only when no
// weighted strategy applies do the shares take all of it, in proportion.) This is how the
// EMLT paper states its mix (§3.4, §4: the bidirectional mutation at 1/3, "the
// probabilities of sampling each proposed mutation type equal"), whatever applies to a path.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "emlt/mcmc/mutation.h"
#include "emlt/run/strategy_stats.h"

namespace emlt {

// The default mixes, also accepted as --mutations presets. The EMLT paper's proportions:
// the bidirectional mutation with probability 1/3, the other strategies sharing the rest.
// MLT (Veach & Guibas 1997):
inline constexpr const char* kMltMix = "bidir=3,lens=2,caustic=2,multichain=2";
// Geometry-aware MLT (mutations/geometry_aware/ga_perturbations.h):
inline constexpr const char* kGamltMix = "bidir=3,ga-lens=2,ga-caustic=2,ga-multichain=2";
// Manifold exploration MLT (Jakob & Marschner 2012; mutations/manifold_perturbation.h): the
// bidirectional mutation and the manifold perturbation, which generalises Veach's three
// perturbations (the paper's §5), in the same 1/3 : 2/3 proportion as the mixes above.
// Mitsuba's mlt with only these two switched on picks each with probability 1/2:
// --mutations bidir=1,manifold=1.
inline constexpr const char* kMemltMix = "bidir=1,manifold=2";
// Ensemble MLT (mutations/ensemble/), all its strategies:
// the paper's mix exactly: the bidirectional mutation at 1/3 of the proposals, the guided
// strategies that apply sharing the rest equally (the guided moves replacing Veach's):
inline constexpr const char* kEmltMix =
    "bidir=1/3,emlt-lens=1,emlt-caustic=1,emlt-multichain=1,emlt-aniso=1,emlt-env=1";
// The other reading of §3.3 ("these can be combined with the original mutation and
// perturbation strategies; this simply adds to the strategies available"): Veach's
// perturbations kept beside the guided ones.
inline constexpr const char* kEmltAddedMix =
    "bidir=1/3,lens=1,caustic=1,multichain=1,emlt-lens=1,emlt-caustic=1,emlt-multichain=1,"
    "emlt-aniso=1,emlt-env=1";
// The paper's ablation (Table 1): the anisotropic path perturbation alone ("Ani") and the
// linear guided perturbations alone ("Lin"), each with the bidirectional mutation at 1/3.
inline constexpr const char* kEmltAniMix = "bidir=1/3,emlt-aniso=1";
inline constexpr const char* kEmltLinMix = "bidir=1/3,emlt-lens=1,emlt-caustic=1,emlt-multichain=1";
// The paper's MLT (§4: "Bidirectional, Lens, Caustic, and Multichain", the bidirectional
// mutation at 1/3); `mlt`'s own default stays Veach's weights above.
inline constexpr const char* kMltPaperMix = "bidir=1/3,lens=1,caustic=1,multichain=1";

// The mix a preset name stands for ("mlt", "mlt-paper", "gamlt", "emlt", "emlt-added",
// "emlt-ani", "emlt-lin", "memlt"), or the
// spec itself when it is not a preset.
std::string expand_mix_preset(const std::string& spec);

// A strategy by name ("bidir", "lens", "caustic", "multichain"); throws emlt::Error listing
// the known names otherwise.
std::unique_ptr<Mutation> make_mutation(const std::string& name);
std::vector<std::string> mutation_names();

// One bit per strategy of a mix (so a mix holds at most kMaxStrategies).
using StrategyMask = uint32_t;
inline constexpr size_t kMaxStrategies = 32;

class StrategyMix {
 public:
  // "name=weight,..." (a bare name has weight 1; "name=p/q" a fixed share); throws
  // emlt::Error on unknown names, non-positive or malformed weights, shares that add up to 1
  // or more, or an empty mix.
  static StrategyMix parse(const std::string& spec);
  void add(std::string name, std::unique_ptr<Mutation> strategy, double weight);
  // A strategy with a fixed share (0 < share < 1) of the proposals.
  void add_share(std::string name, std::unique_ptr<Mutation> strategy, double share);

  size_t size() const { return strategies_.size(); }
  const Mutation& strategy(size_t i) const { return *strategies_[i]; }
  double weight(size_t i) const { return weights_[i]; }
  const std::string& name(size_t i) const { return names_[i]; }

  // Which strategies apply to x: bit i for strategy i. A mask rather than a container, so
  // that a chain's state holds it inline (EMLT visits each of its tens of thousands of
  // chains for one step at a time, and every separate allocation is a cache miss).
  StrategyMask applicable(const Path& x, const MutationContext& ctx) const;
  // Picks a strategy among the applicable ones; -1 when none applies.
  int choose(StrategyMask applicable, float u, double* probability) const;
  double selection_probability(size_t i, StrategyMask applicable) const;

 private:
  std::vector<std::unique_ptr<Mutation>> strategies_;
  std::vector<double> weights_;  // 0 for a strategy with a share
  std::vector<double> shares_;   // 0 for a weighted strategy
  bool has_shares_ = false;
  std::vector<std::string> names_;
  // Sum of the applicable strategies' weights for every mask, while the mix is small
  // enough for a table (summed in index order, as the loop it replaces).
  static constexpr size_t kTabulatedStrategies = 10;
  std::vector<double> totals_;
  std::vector<double> share_totals_;  // likewise, of the applicable strategies' fixed shares
  void tabulate();
  double total_weight(StrategyMask applicable) const;
  // P(i | applicable) when the mix has shares.
  double shared_probability(size_t i, StrategyMask applicable) const;
};

}  // namespace emlt
