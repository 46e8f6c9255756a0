#pragma once
// b, the scale of every path-space chain image (mlt, gamlt, emlt), estimated on while the
// chains run. The bootstrap's b rests on a fixed number of BDPT samples; where most light
// arrives by rare, bright paths (caustics through glass, a lamp behind a lens) those samples
// usually miss them, and the whole image is then too dark by the same factor however long
// the chains run, while b's printed error, computed from samples that saw no such path,
// says it is accurate. This pass draws more samples of the same estimator (the bootstrap's
// streams, numbered on from its last sample) at a fixed rate per chain mutation, so b's
// error shrinks as the chains' does, and the image is scaled by the b of every sample so
// far. At rate 0 it draws none: b is the bootstrap's, to the bit.
//
// Split by path length (mmlt, pss_chains.h): each sample's weights are also summed length by
// length, and b's sums are those of the lengths the render counts (those with chains).
//
// Determinism: samples are summed in groups of consecutive sample numbers counted from the
// bootstrap's end, the groups in order, whatever slices, threads or ranks drew them; a slice
// always ends on a group's end. A stop signal abandons the slice under way (a resumed render
// draws it again to the same bits).
#include <cstdint>
#include <vector>

#include "emlt/core/state_io.h"
#include "emlt/integrators/mlt/bootstrap.h"
#include "emlt/integrators/mlt/normalisation_sums.h"

namespace emlt {

class Scene;

class NormalisationPass {
 public:
  // Consecutive samples summed as one group (the unit of a slice and of the sums' order).
  static constexpr uint64_t kGroup = 1024;

  // `rate`: samples drawn per chain mutation (0: none).
  NormalisationPass(const Scene& scene, const BootstrapParams& params, double rate);

  // Sums every sample's weights length by length as well (before start()): `counted[k]` marks
  // the lengths of params.min_edges + k segments whose weights b's sums take.
  void split_by_length(std::vector<bool> counted);

  // A fresh render: the bootstrap's samples are the first.
  void start(const Bootstrap& bootstrap);
  // A render resumed from a checkpoint that kept only the bootstrap's b, its standard error
  // and its samples (format 4): the sums they imply, the largest sample unknown (0).
  void start(uint64_t samples, double b, double standard_error);

  // Draws the samples due after `mutations` chain mutations (whole groups, every rank's
  // share, exchanged so every rank holds the same sums); false when a stop signal cut the
  // slice short, and then nothing of it is kept. A collective call.
  bool up_to(uint64_t mutations);

  // b's: every length's weights, or the counted lengths' where split.
  const NormalisationSums& sums() const { return sums_; }
  // Where split: each length's (every sample counted in each); empty otherwise.
  const std::vector<NormalisationSums>& lengths() const { return lengths_; }
  uint64_t bootstrap_samples() const { return first_sample_; }
  uint64_t drawn() const { return sums_.samples - first_sample_; }
  double seconds() const { return seconds_; }

  void save(StateWriter& out) const;
  // Throws StateError for figures that cannot be a pass's.
  void load(StateReader& in);

 private:
  // The pass's samples due after `mutations` mutations, in whole groups, within the sample
  // numbers a stream can have.
  uint64_t due(uint64_t mutations) const;
  bool split() const { return !counted_.empty(); }

  const Scene& scene_;
  BootstrapParams params_;
  double rate_;
  uint64_t first_sample_ = 0;  // the bootstrap's samples
  NormalisationSums sums_;
  std::vector<bool> counted_;               // by length, where split
  std::vector<NormalisationSums> lengths_;  // by length, where split
  double seconds_ = 0.0;
};

}  // namespace emlt
