#include "emlt/core/interruption.h"

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
// The temporaries being written, one slot a writing thread (an image and its preview are
// written at once): a slot's name is written by its owner while `valid` is false and read by
// the handler only while it is true; `taken` is claimed by compare-and-swap.
struct TemporarySlot {
  char name[4096];
  std::atomic<bool> valid{false};
  std::atomic<bool> taken{false};
};
constexpr int kTemporarySlots = 4;
TemporarySlot g_temporaries[kTemporarySlots];
thread_local int t_temporary_slot = -1;
static_assert(std::atomic<unsigned>::is_always_lock_free && std::atomic<int>::is_always_lock_free &&
              std::atomic<bool>::is_always_lock_free);

}  // namespace

bool requested() {
  return g_requests.load(std::memory_order_relaxed) != 0;
}

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

bool stop_requested() {
  return (g_requests.load(std::memory_order_relaxed) & kStop) != 0;
}
int stop_signal() {
  return g_signal.load(std::memory_order_relaxed);
}

void request_checkpoint() {
  g_requests.fetch_or(kCheckpoint, std::memory_order_relaxed);
}
bool checkpoint_due() {
  return (g_requests.load(std::memory_order_relaxed) & kCheckpoint) != 0;
}
void clear_checkpoint() {
  g_requests.fetch_and(~kCheckpoint, std::memory_order_relaxed);
}

void stop_after(uint64_t units) {
  g_units.store(0, std::memory_order_relaxed);
  g_stop_after.store(units, std::memory_order_relaxed);
}

void register_temporary(const std::string& path) {
  if (t_temporary_slot >= 0) {  // this thread's previous temporary is done with
    TemporarySlot& mine = g_temporaries[t_temporary_slot];
    mine.valid.store(false, std::memory_order_seq_cst);
    mine.taken.store(false, std::memory_order_seq_cst);
    t_temporary_slot = -1;
  }
  if (path.empty() || path.size() >= sizeof(TemporarySlot::name)) return;
  for (int i = 0; i < kTemporarySlots; ++i) {
    bool expected = false;
    if (!g_temporaries[i].taken.compare_exchange_strong(expected, true)) continue;
    std::memcpy(g_temporaries[i].name, path.c_str(), path.size() + 1);
    g_temporaries[i].valid.store(true, std::memory_order_seq_cst);
    t_temporary_slot = i;
    return;
  }
  // More writers at once than slots: this one is not removed by a second signal.
}

void remove_temporary() {
  for (TemporarySlot& slot : g_temporaries)
    if (slot.valid.load(std::memory_order_seq_cst)) ::unlink(slot.name);
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
