#pragma once
// An allocator that keeps freed blocks for the next allocation of their size class, one
// cache a thread. MLT proposes a new path for every mutation and drops one of the two
// paths after the acceptance test: a vector of path vertices (1-1.5 KB for the usual
// lengths) allocated and freed per mutation, above glibc's per-thread cache limit (1 KB),
// so each went to malloc's shared bins. Blocks are plain operator new memory; a block
// freed on another thread than the one that allocated it (chains move between TBB
// threads) simply joins that thread's cache.
#include <algorithm>
#include <array>
#include <cstddef>
#include <new>
#include <vector>

namespace emlt {

namespace recycling {

// Size classes are multiples of a cache line up to 16 KB; larger requests bypass the cache.
// Fine classes, not powers of two: the 16,384 chains' current paths live as long as the
// render, and rounding each 1.1 KB vector up to 2 KB added 7 MB to the public door's peak.
constexpr size_t kGranule = 64;
constexpr int kClasses = 256;                     // 64 B .. 16 KB
constexpr size_t kKeptBytes = size_t(512) << 10;  // a thread caches at most this much

// Under AddressSanitizer blocks go straight back to the heap, so that a use after free of
// a path's vertices is still caught.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kEnabled = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kEnabled = false;
#else
constexpr bool kEnabled = true;
#endif
#else
constexpr bool kEnabled = true;
#endif

// Set once this thread's cache is destroyed: a vector freed later (a static object's, at
// exit) goes straight back to the heap.
inline thread_local bool t_cache_gone = false;

struct ThreadCache {
  std::array<std::vector<void*>, kClasses + 1> free;  // by class, 1 .. kClasses
  size_t kept_bytes = 0;
  ~ThreadCache() {
    t_cache_gone = true;
    for (auto& blocks : free)
      for (void* block : blocks) ::operator delete(block);
  }
};

inline ThreadCache& cache() {
  thread_local ThreadCache c;
  return c;
}

// The class of a request: its size in granules, rounded up (kClasses + 1: too large).
inline size_t size_class(size_t bytes) {
  const size_t k = (bytes + kGranule - 1) / kGranule;
  return k <= size_t(kClasses) ? std::max<size_t>(k, 1) : size_t(kClasses) + 1;
}

// Every cacheable request gets its whole class, whichever way it is served: a block may
// be freed into another thread's cache and handed out there for any request of its class.
inline void* allocate(size_t bytes) {
  const size_t k = size_class(bytes);
  if (k > size_t(kClasses)) return ::operator new(bytes);
  if (kEnabled && !t_cache_gone) {
    ThreadCache& c = cache();
    if (!c.free[k].empty()) {
      void* block = c.free[k].back();
      c.free[k].pop_back();
      c.kept_bytes -= k * kGranule;
      return block;
    }
  }
  return ::operator new(k* kGranule);
}

inline void deallocate(void* block, size_t bytes) {
  const size_t k = size_class(bytes);
  if (kEnabled && k <= size_t(kClasses) && !t_cache_gone) {
    ThreadCache& c = cache();
    if (c.kept_bytes + k * kGranule <= kKeptBytes) {
      c.free[k].push_back(block);
      c.kept_bytes += k * kGranule;
      return;
    }
  }
  ::operator delete(block);
}

}  // namespace recycling

template <typename T>
struct RecyclingAllocator {
  using value_type = T;
  RecyclingAllocator() = default;
  template <typename U>
  RecyclingAllocator(const RecyclingAllocator<U>&) {}
  T* allocate(size_t n) { return static_cast<T*>(recycling::allocate(n * sizeof(T))); }
  void deallocate(T* p, size_t n) { recycling::deallocate(p, n * sizeof(T)); }
  template <typename U>
  bool operator==(const RecyclingAllocator<U>&) const {
    return true;
  }
};

}  // namespace emlt
