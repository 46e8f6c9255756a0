#include "emlt/mcmc/strategy_mix.h"

#include <sstream>

#include "emlt/core/error.h"

namespace emlt {

std::string expand_mix_preset(const std::string& spec) {
  if (spec == "mlt") return kMltMix;
  if (spec == "gamlt") return kGamltMix;
  if (spec == "emlt") return kEmltMix;
  if (spec == "emlt-ani") return kEmltAniMix;
  if (spec == "emlt-lin") return kEmltLinMix;
  return spec;
}

StrategyMix StrategyMix::parse(const std::string& given) {
  StrategyMix mix;
  const std::string spec = expand_mix_preset(given);
  std::stringstream list(spec);
  std::string item;
  while (std::getline(list, item, ',')) {
    if (item.empty()) continue;
    const auto eq = item.find('=');
    const std::string name = item.substr(0, eq);
    double weight = 1.0;
    if (eq != std::string::npos) {
      const std::string text = item.substr(eq + 1);
      size_t used = 0;
      try {
        weight = std::stod(text, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != text.size() || !(weight > 0.0) || !std::isfinite(weight))
        throw Error("--mutations " + spec + ": weight of '" + name + "' must be a positive number");
    }
    for (const auto& existing : mix.names_)
      if (existing == name) throw Error("--mutations " + spec + ": '" + name + "' given twice");
    mix.add(name, make_mutation(name), weight);
  }
  if (mix.strategies_.empty()) throw Error("--mutations " + spec + ": no strategy given");
  return mix;
}

void StrategyMix::add(std::string name, std::unique_ptr<Mutation> strategy, double weight) {
  if (strategies_.size() >= kMaxStrategies)
    throw Error("--mutations: more than " + std::to_string(kMaxStrategies) + " strategies");
  strategies_.push_back(std::move(strategy));
  weights_.push_back(weight);
  names_.push_back(std::move(name));
  totals_.clear();
  if (weights_.size() <= kTabulatedStrategies) {
    totals_.resize(size_t(1) << weights_.size());
    for (StrategyMask mask = 0; mask < totals_.size(); ++mask) {
      double total = 0.0;
      for (size_t i = 0; i < weights_.size(); ++i)
        if ((mask >> i) & 1u) total += weights_[i];
      totals_[mask] = total;
    }
  }
}

StrategyMask StrategyMix::applicable(const Path& x, const MutationContext& ctx) const {
  StrategyMask mask = 0;
  for (size_t i = 0; i < strategies_.size(); ++i)
    if (strategies_[i]->applies_to(x, ctx)) mask |= StrategyMask(1) << i;
  return mask;
}

namespace {
bool has(StrategyMask mask, size_t i) {
  return (mask >> i) & 1u;
}
}  // namespace

double StrategyMix::total_weight(StrategyMask applicable) const {
  if (!totals_.empty()) return totals_[applicable];
  double total = 0.0;
  for (size_t i = 0; i < weights_.size(); ++i)
    if (has(applicable, i)) total += weights_[i];
  return total;
}

int StrategyMix::choose(StrategyMask applicable, float u, double* probability) const {
  const double total = total_weight(applicable);
  if (total <= 0.0) return -1;
  double target = double(u) * total;
  int chosen = -1;
  for (size_t i = 0; i < weights_.size(); ++i) {
    if (!has(applicable, i)) continue;
    chosen = int(i);
    target -= weights_[i];
    if (target < 0.0) break;
  }
  if (probability) *probability = weights_[size_t(chosen)] / total;
  return chosen;
}

double StrategyMix::selection_probability(size_t i, StrategyMask applicable) const {
  if (!has(applicable, i)) return 0.0;
  return weights_[i] / total_weight(applicable);
}

}  // namespace emlt
