#include "emlt/integrators/pss/pss_normalisation.h"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "emlt/core/cluster.h"
#include "emlt/core/state_io.h"

namespace emlt {

double PssNormalisation::b(const std::vector<bool>& counted) const {
  double b = 0.0;
  for (size_t k = 0; k < lengths.size(); ++k)
    if (counted[k]) b += lengths[k].b();
  return b;
}

double PssNormalisation::error(const std::vector<bool>& counted) const {
  double variance = 0.0;
  for (size_t k = 0; k < lengths.size(); ++k)
    if (counted[k]) variance += lengths[k].error() * lengths[k].error();
  return std::sqrt(variance);
}

uint64_t PssNormalisation::samples(const std::vector<bool>& counted) const {
  uint64_t samples = 0;
  for (size_t k = 0; k < lengths.size(); ++k)
    if (counted[k]) samples += lengths[k].samples;
  return samples;
}

double PssNormalisation::largest_share(const std::vector<bool>& counted) const {
  const double total = b(counted);
  double share = 0.0;
  for (size_t k = 0; k < lengths.size(); ++k)
    if (counted[k] && lengths[k].samples > 0 && total > 0.0)
      share = std::max(share, lengths[k].largest / double(lengths[k].samples) / total);
  return share;
}

PssNormalisation pss_normalisation(const std::vector<NormalisationSums>& seeds,
                                   const std::vector<PssChain>& chains, uint64_t first_owned,
                                   uint64_t end_owned) {
  std::vector<NormalisationSums> of_chain(chains.size());
  for (uint64_t c = first_owned; c < end_owned; ++c)
    of_chain[size_t(c)] = chains[size_t(c)].large_steps;
  if (cluster::size() > 1) {
    StateWriter mine;
    mine.put<uint64_t>(first_owned);
    mine.put<uint64_t>(end_owned);
    for (uint64_t c = first_owned; c < end_owned; ++c) mine.put(of_chain[size_t(c)]);
    for (const std::string_view part : cluster::gather_everywhere(mine.data())) {
      StateReader in(part);
      const uint64_t first = in.get<uint64_t>(), end = in.get<uint64_t>();
      for (uint64_t c = first; c < end && c < chains.size(); ++c)
        of_chain[size_t(c)] = in.get<NormalisationSums>();
    }
  }
  PssNormalisation n{seeds};
  for (size_t c = 0; c < chains.size(); ++c) n.lengths[chains[c].index].add(of_chain[c]);
  return n;
}

}  // namespace emlt
