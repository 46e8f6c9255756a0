#include "emlt/core/error.h"
#include "emlt/mcmc/strategy_mix.h"
#include "mutations/bidirectional.h"

namespace emlt {

std::vector<std::string> mutation_names() { return {"bidir"}; }

std::unique_ptr<Mutation> make_mutation(const std::string& name) {
  if (name == "bidir" || name == "bidirectional") return std::make_unique<BidirectionalMutation>();
  std::string known;
  for (const auto& n : mutation_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown mutation '" + name + "' (available: " + known + ")");
}

}  // namespace emlt
