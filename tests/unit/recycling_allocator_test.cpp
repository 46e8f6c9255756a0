// The allocator behind path vertex vectors: freed blocks come back for the next request of
// their size class, on whichever thread frees them, and a vector's contents are unaffected.
#include "emlt/core/recycling_allocator.h"

#include <gtest/gtest.h>

#include <cstring>
#include <thread>

#include "emlt/path/vertex.h"

using namespace emlt;

TEST(RecyclingAllocator, AFreedBlockServesTheNextRequestOfItsClass) {
  if (!recycling::kEnabled) GTEST_SKIP() << "recycling is off under AddressSanitizer";
  void* a = recycling::allocate(1000);  // the 1,024-byte class
  std::memset(a, 0xab, 1024);           // the whole class is usable
  recycling::deallocate(a, 1000);
  void* b = recycling::allocate(970);  // another size of the same class
  EXPECT_EQ(a, b);
  void* c = recycling::allocate(1100);  // another class: a new block
  EXPECT_NE(c, b);
  recycling::deallocate(b, 970);
  recycling::deallocate(c, 1100);
  void* big = recycling::allocate(size_t(1) << 20);  // beyond the classes: the heap's own
  recycling::deallocate(big, size_t(1) << 20);
}

TEST(RecyclingAllocator, BlocksFreedOnAnotherThreadJoinItsCache) {
  if (!recycling::kEnabled) GTEST_SKIP() << "recycling is off under AddressSanitizer";
  void* made = nullptr;
  std::thread maker([&] { made = recycling::allocate(300); });
  maker.join();
  // Freed on a fresh thread, whose cache starts empty (this test thread's may already be
  // full from earlier tests in the same process, and would hand the block to the heap).
  void* again = nullptr;
  bool cached = false;
  std::thread taker([&] {
    recycling::deallocate(made, 300);  // freed here: this thread's cache now has it
    // (Seen in the cache itself: glibc's own per-thread cache would also hand it back.)
    const auto& kept = recycling::cache().free[recycling::size_class(300)];
    cached = !kept.empty() && kept.back() == made;
    again = recycling::allocate(320);  // the same 320-byte class
    std::memset(again, 0, 320);
    recycling::deallocate(again, 320);
  });
  taker.join();
  EXPECT_TRUE(cached);
  EXPECT_EQ(again, made);
}

TEST(RecyclingAllocator, PathVertexVectorsKeepTheirContentsThroughGrowthAndReuse) {
  for (int round = 0; round < 3; ++round) {
    PathVertices path;
    for (int i = 0; i < 40; ++i) {  // grows through many classes, past 6 KB
      PathVertex v;
      v.position = Vec3(float(i), float(round), 1.0f);
      v.pdf_from_eye = float(i) * 0.5f;
      path.push_back(v);
    }
    PathVertices copy = path;
    for (int i = 0; i < 40; ++i) {
      ASSERT_EQ(copy[size_t(i)].position, Vec3(float(i), float(round), 1.0f));
      ASSERT_EQ(copy[size_t(i)].pdf_from_eye, float(i) * 0.5f);
    }
  }
}
