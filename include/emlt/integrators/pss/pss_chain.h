#pragma once
// One chain of primary-sample-space MLT (pssmlt, mmlt): its unit-cube coordinates, the
// sample they give, and how a checkpoint keeps it.
#include <cstdint>

#include "emlt/core/rng.h"
#include "emlt/core/state_io.h"
#include "emlt/integrators/mlt/normalisation_sums.h"
#include "emlt/integrators/pss/primary_sample_tracer.h"
#include "emlt/integrators/pss/primary_sample_vector.h"

namespace emlt {

struct PssChain {
  PrimarySampleVector u;
  PssSample current;
  double carried = 0.0;  // (1 - a) summed over the steps since x became current
  Rng rng;
  int length = 0;      // MMLT: the chain's path length
  size_t index = 0;    // MMLT: the length's index among all lengths (0 for PSSMLT)
  size_t layer = 1;    // the film layer of its chains' part (pss_chains.h)
  double b = 0.0;      // the bootstrap's normalisation its weights use (b, or b_k)
  double scale = 1.0;  // MMLT: (b_k / b) (chains / chains of length k); 1 for PSSMLT
  uint64_t steps = 0;  // taken since the chains began
  // f* of every large step's proposal: independent uniform primary samples, whose mean is
  // b (b_k) (pss_normalisation.h).
  NormalisationSums large_steps;

  // What a checkpoint keeps: the state after the bootstrap's (length, index, layer, b,
  // scale), which the render derives again. load() throws StateError for a chain that is
  // inconsistent or splats outside a width x height image.
  void save(StateWriter& out) const;
  void load(StateReader& in, int width, int height);
};

}  // namespace emlt
