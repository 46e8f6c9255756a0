#include "emlt/mcmc/strategy_mix.h"

#include <sstream>

#include "emlt/core/error.h"

namespace emlt {

std::string expand_mix_preset(const std::string& spec) {
  if (spec == "mlt") return kMltMix;
  if (spec == "mlt-paper") return kMltPaperMix;
  if (spec == "emlt-added") return kEmltAddedMix;
  if (spec == "gamlt") return kGamltMix;
  if (spec == "memlt") return kMemltMix;
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
    bool share = false;
    if (eq != std::string::npos && item.find('/', eq) != std::string::npos) {
      // A fixed share p/q.
      const std::string text = item.substr(eq + 1);
      const auto slash = text.find('/');
      double p = 0.0, q = 0.0;
      size_t used_p = 0, used_q = 0;
      try {
        p = std::stod(text.substr(0, slash), &used_p);
        q = std::stod(text.substr(slash + 1), &used_q);
      } catch (const std::exception&) {
        used_p = used_q = 0;
      }
      weight = p / q;
      if (used_p != slash || used_q != text.size() - slash - 1 || !(weight > 0.0) ||
          !(weight < 1.0) || !std::isfinite(weight))
        throw Error("--mutations " + spec + ": share of '" + name +
                    "' must be a fraction p/q between 0 and 1");
      share = true;
    } else if (eq != std::string::npos) {
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
    if (share)
      mix.add_share(name, make_mutation(name), weight);
    else
      mix.add(name, make_mutation(name), weight);
  }
  double shares = 0.0;
  for (const double s : mix.shares_) shares += s;
  if (shares >= 1.0) throw Error("--mutations " + spec + ": the fixed shares add up to 1 or more");
  if (mix.strategies_.empty()) throw Error("--mutations " + spec + ": no strategy given");
  return mix;
}

void StrategyMix::add(std::string name, std::unique_ptr<Mutation> strategy, double weight) {
  if (strategies_.size() >= kMaxStrategies)
    throw Error("--mutations: more than " + std::to_string(kMaxStrategies) + " strategies");
  strategies_.push_back(std::move(strategy));
  weights_.push_back(weight);
  shares_.push_back(0.0);
  names_.push_back(std::move(name));
  tabulate();
}

void StrategyMix::tabulate() {
  totals_.clear();
  share_totals_.clear();
  if (weights_.size() > kTabulatedStrategies) return;
  totals_.resize(size_t(1) << weights_.size());
  share_totals_.resize(totals_.size());
  for (StrategyMask mask = 0; mask < totals_.size(); ++mask) {
    double total = 0.0, shares = 0.0;
    for (size_t i = 0; i < weights_.size(); ++i)
      if ((mask >> i) & 1u) {
        total += weights_[i];
        shares += shares_[i];
      }
    totals_[mask] = total;
    share_totals_[mask] = shares;
  }
}

void StrategyMix::add_share(std::string name, std::unique_ptr<Mutation> strategy, double share) {
  add(std::move(name), std::move(strategy), 0.0);
  shares_.back() = share;
  has_shares_ = true;
  tabulate();
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

double StrategyMix::shared_probability(size_t i, StrategyMask applicable) const {
  if (!has(applicable, i)) return 0.0;
  double shares = 0.0;
  if (!share_totals_.empty()) {
    shares = share_totals_[applicable];
  } else {
    for (size_t j = 0; j < shares_.size(); ++j)
      if (has(applicable, j)) shares += shares_[j];
  }
  const double weights = total_weight(applicable);
  if (weights > 0.0) return shares_[i] > 0.0 ? shares_[i] : (1.0 - shares) * weights_[i] / weights;
  return shares > 0.0 ? shares_[i] / shares : 0.0;
}

int StrategyMix::choose(StrategyMask applicable, float u, double* probability) const {
  if (has_shares_) {
    // Walk the applicable strategies' probabilities in index order.
    double target = double(u);
    int chosen = -1;
    double p = 0.0;
    for (size_t i = 0; i < strategies_.size(); ++i) {
      if (!has(applicable, i)) continue;
      const double pi = shared_probability(i, applicable);
      if (!(pi > 0.0)) continue;
      chosen = int(i);
      p = pi;
      target -= pi;
      if (target < 0.0) break;
    }
    if (probability) *probability = p;
    return chosen;
  }
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
  if (has_shares_) return shared_probability(i, applicable);
  return weights_[i] / total_weight(applicable);
}

}  // namespace emlt
