#pragma once
// An allocator that keeps freed blocks for the next allocation of their size class, one
// cache a thread. MLT proposes a new path for every mutation and drops one of the two
// paths after the acceptance test: a vector of path vertices (1-1.5 KB for the usual
// lengths) allocated and freed per mutation, above glibc's per-thread cache limit (1 KB),
// so each went to malloc's shared bins. Blocks are plain operator new memory; a block
// freed on another thread than the one that allocated it (chains move between TBB
// threads) simply joins that thread's cache.
#include <array>
#include <cstddef>
#include <new>
#include <vector>

namespace emlt {

namespace recycling {

// Size classes are powers of two from 2^kMinShift bytes; larger requests bypass the cache.
constexpr int kMinShift = 8, kClasses = 8;  // 256 B .. 32 KB
constexpr size_t kKeptPerClass = 64;        // a thread keeps at most this many per class

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
  std::array<std::vector<void*>, kClasses> free;
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

inline int size_class(size_t bytes) {
  int k = 0;
  while (k < kClasses && (size_t(1) << (kMinShift + k)) < bytes) ++k;
  return k;  // kClasses: too large to cache
}

// Every cacheable request gets a whole size class, whichever way it is served: a block may
// be freed into another thread's cache and handed out there for any request of its class.
inline void* allocate(size_t bytes) {
  const int k = size_class(bytes);
  if (k == kClasses) return ::operator new(bytes);
  if (kEnabled && !t_cache_gone) {
    auto& blocks = cache().free[size_t(k)];
    if (!blocks.empty()) {
      void* block = blocks.back();
      blocks.pop_back();
      return block;
    }
  }
  return ::operator new(size_t(1) << (kMinShift + k));
}

inline void deallocate(void* block, size_t bytes) {
  const int k = size_class(bytes);
  if (kEnabled && k < kClasses && !t_cache_gone) {
    auto& blocks = cache().free[size_t(k)];
    if (blocks.size() < kKeptPerClass) {
      blocks.push_back(block);
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
