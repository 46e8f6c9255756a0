#include "mutations/ensemble/density_jump.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mutations/ensemble/guide_spread.h"

namespace emlt::ensemble {

GuideMixture fit_guide_mixture(std::span<const Vec2> centres, double min_bandwidth) {
  GuideMixture mixture;
  mixture.centres = centres;
  const double scott =
      guide_spread(centres) * std::pow(double(std::max<size_t>(centres.size(), 1)), -1.0 / 6.0);
  mixture.bandwidth = std::max(scott, min_bandwidth);
  return mixture;
}

Vec2 sample_guide_mixture(const GuideMixture& mixture, Rng& rng) {
  const Vec2 centre = mixture.centres[rng.uniform_index(uint32_t(mixture.centres.size()))];
  // Box-Muller in double; 1 - u keeps the logarithm finite.
  const double r = mixture.bandwidth * std::sqrt(-2.0 * std::log(1.0 - rng.uniform_double()));
  const double phi = 2.0 * M_PI * rng.uniform_double();
  return Vec2(float(double(centre.x) + r * std::cos(phi)),
              float(double(centre.y) + r * std::sin(phi)));
}

double guide_mixture_log_density(const GuideMixture& mixture, const Vec2& u) {
  if (mixture.centres.empty()) return -std::numeric_limits<double>::infinity();
  const double inv_two_h2 = 0.5 / (mixture.bandwidth * mixture.bandwidth);
  const auto exponent = [&](const Vec2& centre) {
    const double dx = double(u.x) - double(centre.x), dy = double(u.y) - double(centre.y);
    return -(dx * dx + dy * dy) * inv_two_h2;
  };
  double largest = -std::numeric_limits<double>::infinity();
  for (const Vec2& centre : mixture.centres) largest = std::max(largest, exponent(centre));
  double sum = 0.0;
  for (const Vec2& centre : mixture.centres) sum += std::exp(exponent(centre) - largest);
  return largest + std::log(sum / double(mixture.centres.size())) -
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
