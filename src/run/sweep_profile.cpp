#include "emlt/run/sweep_profile.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "emlt/core/cluster.h"

namespace emlt {

SweepProfile::SweepProfile() : enabled(std::getenv("EMLT_MPI_PROFILE") != nullptr) {}

double SweepProfile::now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double SweepProfile::thread_cpu() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

void SweepProfile::print() const {
  if (!enabled) return;
  std::fprintf(stderr,
               "emlt: profile rank %d: steps %.2f s (cpu %.2f s), guides %.2f s, agreement "
               "%.2f s, exchange %.2f s (pack %.2f, allgather %.2f, unpack %.2f; %.0f MB "
               "sent)\n",
               cluster::rank(), steps, steps_cpu, guides, agreement, pack + gather + unpack, pack,
               gather, unpack, double(bytes_sent) / 1e6);
}

}  // namespace emlt
