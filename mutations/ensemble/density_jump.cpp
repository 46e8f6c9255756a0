#include "mutations/ensemble/density_jump.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mutations/ensemble/guide_spread.h"

namespace emlt::ensemble {

GuideMixture fit_guide_mixture(std::span<const Vec2> centres, double min_bandwidth,
                               std::span<const double> weights) {
  GuideMixture mixture;
  mixture.centres = centres;
  if (weights.size() == centres.size()) {
    double total = 0.0;
    for (const double w : weights) total += w;
    if (total > 0.0 && std::isfinite(total)) {
      mixture.weights = weights;
      mixture.weight_total = total;
    }
  }
  const double scott =
      guide_spread(centres) * std::pow(double(std::max<size_t>(centres.size(), 1)), -1.0 / 6.0);
  mixture.bandwidth = std::max(scott, min_bandwidth);
  return mixture;
}

Vec2 sample_guide_mixture(const GuideMixture& mixture, Rng& rng) {
  size_t pick = rng.uniform_index(uint32_t(mixture.centres.size()));
  if (!mixture.weights.empty()) {
    double u = rng.uniform_double() * mixture.weight_total;
    pick = mixture.centres.size() - 1;
    for (size_t n = 0; n < mixture.centres.size(); ++n)
      if ((u -= mixture.weights[n]) < 0.0) {
        pick = n;
        break;
      }
  }
  const Vec2 centre = mixture.centres[pick];
  // Box-Muller in double; 1 - u keeps the logarithm finite.
  const double r = mixture.bandwidth * std::sqrt(-2.0 * std::log(1.0 - rng.uniform_double()));
  const double phi = 2.0 * M_PI * rng.uniform_double();
  return Vec2(float(double(centre.x) + r * std::cos(phi)),
              float(double(centre.y) + r * std::sin(phi)));
}

double guide_mixture_log_density(const GuideMixture& mixture, const Vec2& u) {
  if (mixture.centres.empty()) return -std::numeric_limits<double>::infinity();
  const bool weighted = !mixture.weights.empty();
  const double inv_two_h2 = 0.5 / (mixture.bandwidth * mixture.bandwidth);
  const auto exponent = [&](size_t n) {
    const Vec2& centre = mixture.centres[n];
    const double dx = double(u.x) - double(centre.x), dy = double(u.y) - double(centre.y);
    return -(dx * dx + dy * dy) * inv_two_h2;
  };
  double largest = -std::numeric_limits<double>::infinity();
  for (size_t n = 0; n < mixture.centres.size(); ++n)
    if (!weighted || mixture.weights[n] > 0.0) largest = std::max(largest, exponent(n));
  double sum = 0.0;
  for (size_t n = 0; n < mixture.centres.size(); ++n)
    sum += (weighted ? mixture.weights[n] : 1.0) * std::exp(exponent(n) - largest);
  const double total = weighted ? mixture.weight_total : double(mixture.centres.size());
  return largest + std::log(sum / total) -
         std::log(2.0 * M_PI * mixture.bandwidth * mixture.bandwidth);
}

JumpProposal propose_jump(const Vec2& x, const GuideMixture& mixture, Rng& rng) {
  JumpProposal proposal;
  proposal.state = sample_guide_mixture(mixture, rng);
  proposal.log_density_ratio =
      guide_mixture_log_density(mixture, x) - guide_mixture_log_density(mixture, proposal.state);
  return proposal;
}

}  // namespace emlt::ensemble
