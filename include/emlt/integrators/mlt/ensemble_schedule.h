#pragma once
// Ensemble MLT's schedule (Bashford-Rogers et al. 2021, paper §3.4): the chains form two
// ensembles X and Y of E paths each; X takes `it` steps per path guided by the frozen Y
// (ensemble_guides.h), then the two swap roles. Each X step keeps f invariant for a fixed
// Y, so each half-sweep preserves the product density of both ensembles.
//
// Under MPI each rank moves a share of X's chains and holds the others' only as guide
// copies (PathCodec's guide form): after a half-sweep every rank sends the paths its
// chains moved, as they are the frozen half that guides the next one.
#include <tbb/task_arena.h>

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "emlt/core/state_io.h"
#include "emlt/integrators/mlt/mlt_chain.h"
#include "emlt/mcmc/ensemble_guides.h"
#include "emlt/run/sweep_profile.h"
#include "emlt/settings/settings.h"

namespace emlt {

class Scene;

class EnsembleSchedule {
 public:
  // E and `it` from the settings, or the paper's E = 16384 with it = floor(W H / 2E), which
  // assumes images of at least 2E pixels; on smaller ones E shrinks to W H / 2 so that every
  // path still moves once per half-sweep. `base`: the guides' parameters before the
  // settings' overrides.
  EnsembleSchedule(const Scene& scene, const RenderSettings& settings, EnsembleParams base,
                   uint64_t pixels);

  uint64_t size() const { return size_; }
  uint64_t iterations() const { return iterations_; }
  const EnsembleParams& params() const { return params_; }
  const EnsembleGuides& guides() const { return guides_; }

  // What a checkpoint keeps of the schedule (in the chains' section): the half that moves,
  // the sum of the swaps' α, the swaps and the seconds spent building guides.
  uint64_t half = 0;
  double alpha_sum = 0.0;
  uint64_t swaps = 0;
  double tree_seconds = 0.0;

  // Before a half-sweep: Y's guides from the frozen half (the other one than the sweep's),
  // which nothing changes during the sweep, so rebuilding them on resume gives the same
  // guides. Built on the render's threads (`arena`), not every core of the machine. A new
  // half-sweep also adds the guides' α to alpha_sum; a resumed one only rebuilds them when
  // they are not built yet.
  void begin_half_sweep(const std::vector<MltChain>& chains, tbb::task_arena& arena);
  void continue_half_sweep(const std::vector<MltChain>& chains, tbb::task_arena& arena);
  // After a whole half-sweep (every rank's): the other half moves next.
  void swap();

  // Under MPI: whether this rank holds other ranks' chains as guide copies.
  bool guide_copies() const { return guide_copies_; }
  // `blocks` of chains pack their moved paths apart, in block order; the guides' and the
  // exchange's times go into `profile` (kept by reference).
  void attach(size_t blocks, SweepProfile& profile);
  // Packs chain c's path, which moved, for the others (by the block that moved it, while
  // the path is in cache).
  void pack_moved(std::vector<MltChain>& chains, uint64_t c, size_t block);
  // What this rank sends of the packed paths: returns every rank's length in bytes as far
  // as this rank knows it (its own; zeros for the others), whose maxima over the ranks are
  // every rank's.
  std::vector<uint64_t> prepare_moved_paths();
  // Sends what prepare_moved_paths() prepared, every rank's length known, and takes in the
  // other ranks' paths.
  void share_moved_paths(std::vector<MltChain>& chains, std::span<const uint64_t> lengths);
  // A resumed rank holds only its own chains (MltChain::save): every rank sends them, and
  // the others' guide copies are whole again.
  void resend_own(std::vector<MltChain>& chains, const std::function<bool(uint64_t)>& owns_chain);

 private:
  void build_guides(const std::vector<MltChain>& chains, tbb::task_arena& arena);

  uint64_t size_, iterations_;
  EnsembleParams params_;
  EnsembleGuides guides_;
  std::vector<const Path*> frozen_;
  bool guides_ready_ = false;
  int width_, height_;
  uint64_t seed_;
  SweepProfile* profile_ = nullptr;
  bool guide_copies_;
  // Only the paths that moved are sent: the others are as every rank already has them.
  // The writers are kept across swaps, with their memory.
  struct PackedPaths {
    std::vector<uint32_t> ids;
    StateWriter records;  // for each of ids: the chain's target, its path in guide form
  };
  std::vector<PackedPaths> packed_;
  StateWriter exchange_;
  std::vector<uint32_t> all_ids_;
};

}  // namespace emlt
