#include "emlt/core/error.h"
#include "emlt/mcmc/strategy_mix.h"
#include "mutations/bidirectional.h"
#include "mutations/caustic_perturbation.h"
#include "mutations/ensemble/anisotropic_path.h"
#include "mutations/ensemble/density_jump_lens.h"
#include "mutations/ensemble/environment_perturbation.h"
#include "mutations/ensemble/guided_caustic.h"
#include "mutations/ensemble/guided_lens.h"
#include "mutations/ensemble/guided_multichain.h"
#include "mutations/ensemble/spread_scaled_perturbation.h"
#include "mutations/geometry_aware/ga_perturbations.h"
#include "mutations/lens_perturbation.h"
#include "mutations/manifold_perturbation.h"
#include "mutations/multichain_perturbation.h"

namespace emlt {

std::vector<std::string> mutation_names() {
  return {"bidir",
          "lens",
          "caustic",
          "multichain",
          "manifold",
          "ga-lens",
          "ga-caustic",
          "ga-multichain",
          "emlt-lens",
          "emlt-caustic",
          "emlt-multichain",
          "emlt-aniso",
          "emlt-env",
          "emlt-jump",
          "emlt-jump-near",
          "emlt-spread-lens",
          "emlt-spread-caustic",
          "emlt-spread-multichain"};
}

std::unique_ptr<Mutation> make_mutation(const std::string& name) {
  if (name == "bidir" || name == "bidirectional") return std::make_unique<BidirectionalMutation>();
  if (name == "lens") return std::make_unique<LensPerturbation>();
  if (name == "caustic") return std::make_unique<CausticPerturbation>();
  if (name == "multichain" || name == "multi-chain")
    return std::make_unique<MultiChainPerturbation>();
  if (name == "manifold") return std::make_unique<ManifoldPerturbation>();
  if (name == "ga-lens") return std::make_unique<GaLensPerturbation>();
  if (name == "ga-caustic") return std::make_unique<GaCausticPerturbation>();
  if (name == "ga-multichain" || name == "ga-multi-chain")
    return std::make_unique<GaMultiChainPerturbation>();
  if (name == "emlt-lens") return std::make_unique<GuidedLensPerturbation>();
  if (name == "emlt-caustic") return std::make_unique<GuidedCausticPerturbation>();
  if (name == "emlt-multichain" || name == "emlt-multi-chain")
    return std::make_unique<GuidedMultiChainPerturbation>();
  if (name == "emlt-aniso") return std::make_unique<AnisotropicPathPerturbation>();
  if (name == "emlt-env") return std::make_unique<EnvironmentPerturbation>();
  // The ensemble-informed variants beyond the paper (docs/experiments.md, "Beyond the paper").
  if (name == "emlt-jump") return std::make_unique<DensityJumpLens>();
  if (name == "emlt-jump-near") return std::make_unique<DensityJumpLens>(true);
  if (name == "emlt-spread-lens")
    return std::make_unique<SpreadScaledPerturbation>(name, std::make_unique<LensPerturbation>());
  if (name == "emlt-spread-caustic")
    return std::make_unique<SpreadScaledPerturbation>(name,
                                                      std::make_unique<CausticPerturbation>());
  if (name == "emlt-spread-multichain")
    return std::make_unique<SpreadScaledPerturbation>(name,
                                                      std::make_unique<MultiChainPerturbation>());
  std::string known;
  for (const auto& n : mutation_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown mutation '" + name + "' (available: " + known + ")");
}

}  // namespace emlt
