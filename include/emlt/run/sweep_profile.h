#pragma once
// EMLT_MPI_PROFILE=1 (docs/scaling.md): every rank prints where its chains' loop spent its
// time: taking steps (wall time, and the calling thread's CPU time, which falls short of it
// when the rank was not running), building EMLT's guides, waiting at the per-sweep
// agreement (for the slowest rank, mostly), and EMLT's exchange of moved paths ("pack":
// joining what the blocks packed as their chains took their steps; MPI's allgather;
// unpacking the other ranks' paths).
#include <cstdint>

namespace emlt {

struct SweepProfile {
  bool enabled;
  double steps = 0.0, steps_cpu = 0.0, guides = 0.0, agreement = 0.0, pack = 0.0, gather = 0.0,
         unpack = 0.0;
  uint64_t bytes_sent = 0;

  SweepProfile();
  static double now();
  static double thread_cpu();
  void print() const;
};

}  // namespace emlt
