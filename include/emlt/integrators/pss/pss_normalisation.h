#pragma once
// b (for MMLT each path length's b_k) as pssmlt and mmlt scale their chains' part of the
// image by at the end (pss_chains.h): the mean of f* (f*_k) over independent uniform primary
// samples. Every large step draws each coordinate it reads afresh, so its proposal is such a
// sample whether or not it is accepted, whatever the chain's state; with the bootstrap's
// samples of the seeds (the same kind, drawn before the chains) they give a b whose error
// shrinks as the render runs, at no cost beyond the sums.
//
// The path-space bootstrap's b (bootstrap.h), from BDPT samples, stays the b of the splats'
// weights: it is fixed before the chains and any fixed b keeps the estimator unbiased; only
// the scale of the chains' part must converge. For mmlt its samples, split by length, and
// those drawn beside the chains are pooled with these (pss_chains.h).
//
// Determinism: each chain sums its own large steps in its order of steps; the sums here add,
// for each length, the seeds' sums (in sample order), then the chains' in chain order, so the
// same bits come at any thread or rank count and across a stop and resume.
#include <cstdint>
#include <vector>

#include "emlt/integrators/mlt/normalisation_sums.h"
#include "emlt/integrators/pss/pss_chain.h"

namespace emlt {

struct PssNormalisation {
  std::vector<NormalisationSums> lengths;  // by the chains' length index (PssChain::index)

  // b, the sum of the lengths' b_k, of the lengths `counted` marks (those with chains).
  double b(const std::vector<bool>& counted) const;
  // b's printed error: the lengths' samples are disjoint, so their errors add in quadrature.
  double error(const std::vector<bool>& counted) const;
  uint64_t samples(const std::vector<bool>& counted) const;
  // The largest single sample's share of b (its b_k's sample over the count, over b).
  double largest_share(const std::vector<bool>& counted) const;
};

// The sums of every length: `seeds` (the bootstrap's, by length index), then each chain's
// large steps in chain order. `chains` holds every rank's chains, of which this rank runs
// [first_owned, end_owned) and knows only those; the others' sums are exchanged, so every
// rank gets the same figures (a collective call under MPI).
PssNormalisation pss_normalisation(const std::vector<NormalisationSums>& seeds,
                                   const std::vector<PssChain>& chains, uint64_t first_owned,
                                   uint64_t end_owned);

}  // namespace emlt
