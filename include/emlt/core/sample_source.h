#pragma once
// A source of uniform numbers in [0, 1) other than a PCG stream: primary-sample-space MLT
// drives the path tracer and the subpath walks from the coordinates of its chain state
// (integrators/pss/primary_sample_vector.h). The renderers keep their Rng versions (the same code,
// instantiated for Rng, so their images keep their bits); these overloads take this.
#include "emlt/core/math.h"

namespace emlt {

class SampleSource {
 public:
  virtual ~SampleSource() = default;
  virtual float uniform() = 0;
  Vec2 uniform2() {
    const float a = uniform();
    return {a, uniform()};
  }
};

}  // namespace emlt
