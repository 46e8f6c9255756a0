#include "emlt/render/interruption.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstring>
#include <vector>

#include "emlt/core/cluster.h"

namespace emlt::interruption {

namespace {

constexpr unsigned kStop = 1u, kCheckpoint = 2u;

// Lock-free atomics only: the signal handler writes them.
std::atomic<unsigned> g_requests{0};
std::atomic<int> g_signal{0};
std::atomic<uint64_t> g_stop_after{0};
std::atomic<uint64_t> g_units{0};
// The registered temporary's name: written by the main thread while g_temporary_valid is
// false, read by the handler only while it is true.
char g_temporary[4096];
std::atomic<bool> g_temporary_valid{false};
static_assert(std::atomic<unsigned>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

}  // namespace

bool requested() { return g_requests.load(std::memory_order_relaxed) != 0; }

bool poll(uint64_t units) {
  if (const uint64_t limit = g_stop_after.load(std::memory_order_relaxed); limit > 0) {
    if (g_units.fetch_add(units, std::memory_order_relaxed) + units >= limit) request_stop(SIGINT);
  }
  return requested();
}

void request_stop(int signal) {
  int none = 0;
  g_signal.compare_exchange_strong(none, signal, std::memory_order_relaxed);
  g_requests.fetch_or(kStop, std::memory_order_relaxed);
}

bool stop_requested() { return (g_requests.load(std::memory_order_relaxed) & kStop) != 0; }
int stop_signal() { return g_signal.load(std::memory_order_relaxed); }

void request_checkpoint() { g_requests.fetch_or(kCheckpoint, std::memory_order_relaxed); }
bool checkpoint_due() { return (g_requests.load(std::memory_order_relaxed) & kCheckpoint) != 0; }
void clear_checkpoint() { g_requests.fetch_and(~kCheckpoint, std::memory_order_relaxed); }

void stop_after(uint64_t units) {
  g_units.store(0, std::memory_order_relaxed);
  g_stop_after.store(units, std::memory_order_relaxed);
}

void register_temporary(const std::string& path) {
  g_temporary_valid.store(false, std::memory_order_seq_cst);
  if (path.empty() || path.size() >= sizeof(g_temporary)) return;
  std::memcpy(g_temporary, path.c_str(), path.size() + 1);
  g_temporary_valid.store(true, std::memory_order_seq_cst);
}

void remove_temporary() {
  if (g_temporary_valid.load(std::memory_order_seq_cst)) ::unlink(g_temporary);
}

Decision agree(bool incomplete, std::span<uint64_t> maxima) {
  if (cluster::size() == 1) return {incomplete, stop_requested(), checkpoint_due()};
  // One reduction, since every collective waits for the slowest rank to reach it (under
  // load, for the scheduler to run it): "on any rank" is the maximum of 0/1 flags, and the
  // signal passed on is the largest.
  std::vector<uint64_t> flags = {uint64_t(incomplete), uint64_t(stop_requested()),
                                 uint64_t(checkpoint_due()), uint64_t(std::max(stop_signal(), 0))};
  flags.insert(flags.end(), maxima.begin(), maxima.end());
  cluster::max_everywhere(flags);
  std::copy(flags.begin() + 4, flags.end(), maxima.begin());
  const int signal = int(flags[3]);
  const Decision decision{flags[0] > 0, flags[1] > 0, flags[2] > 0};
  if (decision.stop && !stop_requested()) request_stop(signal > 0 ? signal : SIGINT);
  if (decision.checkpoint) request_checkpoint();
  return decision;
}

void reset() {
  g_requests.store(0, std::memory_order_relaxed);
  g_signal.store(0, std::memory_order_relaxed);
  g_units.store(0, std::memory_order_relaxed);
  g_stop_after.store(0, std::memory_order_relaxed);
}

}  // namespace emlt::interruption
