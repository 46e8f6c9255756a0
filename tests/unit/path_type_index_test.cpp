#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <set>

#include "emlt/core/rng.h"
#include "emlt/mcmc/path_type_index.h"

using namespace emlt;

namespace {
PathType type_of(int vertices, uint64_t mask) {
  PathType t;
  t.vertices = uint8_t(vertices);
  t.specular_mask = mask;
  return t;
}

std::vector<PathType> random_ensemble(size_t n) {
  Rng rng(3, 0);
  std::vector<PathType> types;
  for (size_t i = 0; i < n; ++i) {
    const int vertices = 3 + int(rng.uniform_index(4));
    uint64_t mask = 0;
    for (int v = 1; v + 1 < vertices; ++v)
      if (rng.uniform() < 0.3f) mask |= uint64_t(1) << v;
    types.push_back(type_of(vertices, mask));
  }
  return types;
}
}  // namespace

TEST(PathTypeIndex, GroupsEveryMemberUnderItsOwnTypeInEnsembleOrder) {
  const auto types = random_ensemble(5000);
  PathTypeIndex index;
  index.build(types);
  size_t total = 0;
  std::set<std::pair<int, uint64_t>> seen;
  for (const PathType& t : types) {
    if (!seen.insert({t.vertices, t.specular_mask}).second) continue;
    const auto members = index.members(t);
    total += members.size();
    for (size_t i = 0; i < members.size(); ++i) {
      EXPECT_EQ(types[members[i]].vertices, t.vertices);
      EXPECT_EQ(types[members[i]].specular_mask, t.specular_mask);
      if (i > 0) {
        EXPECT_LT(members[i - 1], members[i]);
      }
    }
  }
  EXPECT_EQ(total, types.size());
  EXPECT_EQ(index.type_count(), seen.size());
  EXPECT_TRUE(index.members(type_of(9, 0)).empty());
}

TEST(PathTypeIndex, GuidesAreDeterministicAndOfTheSameType) {
  const auto types = random_ensemble(2000);
  PathTypeIndex index;
  index.build(types);
  const PathType t = types[17];
  const auto a = index.guides(t, 1, 5, 100, 8), b = index.guides(t, 1, 5, 100, 8);
  EXPECT_EQ(a, b);  // same (type, seed, chain, step): same Upsilon in both directions
  ASSERT_EQ(a.size(), std::min<size_t>(8, index.members(t).size()));
  for (uint32_t g : a) {
    EXPECT_EQ(types[g].vertices, t.vertices);
    EXPECT_EQ(types[g].specular_mask, t.specular_mask);
  }
  // Other steps and chains look at other windows of the list.
  int different = 0;
  for (uint64_t step = 101; step < 121; ++step) different += index.guides(t, 1, 5, step, 8) != a;
  EXPECT_GT(different, 15);
  EXPECT_TRUE(index.guides(type_of(9, 0), 1, 5, 100, 8).empty());
}

TEST(PathTypeIndex, BuildIsTheSameOnOneAndTwoThreads) {
  const auto types = random_ensemble(20000);
  PathTypeIndex one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one.build(types);
  }
  two.build(types);
  for (const PathType& t : {types[0], types[1], types[2], types[500]}) {
    const auto a = one.members(t), b = two.members(t);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin()));
    EXPECT_EQ(one.guides(t, 7, 3, 9, 16), two.guides(t, 7, 3, 9, 16));
  }
}

#include "emlt/mcmc/adaptive_alpha.h"

TEST(EnsembleAdaptiveAlpha, FollowsThePapersSigmoidBetweenTheBounds) {
  using namespace emlt::ensemble;
  // Coverage: a 10 x 20 px box in a 100 x 100 image is 2 %.
  const std::vector<Vec2> clustered = {{10, 10}, {20, 30}, {15, 12}};
  EXPECT_NEAR(image_coverage(clustered, 100, 100), 0.02, 1e-9);
  EXPECT_EQ(image_coverage(std::vector<Vec2>{{5, 5}}, 100, 100), 0.0);
  // At the centre c = 0.1 the weight is 1/2: alpha is the mean of the bounds.
  EXPECT_NEAR(adaptive_alpha(0.1), 0.5 * (0.5 + 0.05), 1e-12);
  // Clustered guides get (nearly) the large step, spread ones the small.
  EXPECT_NEAR(adaptive_alpha(0.0), 0.5, 0.01);
  EXPECT_NEAR(adaptive_alpha(0.02), 0.5 - 0.45 / (1.0 + std::exp(4.0)), 1e-12);
  EXPECT_NEAR(adaptive_alpha(1.0), 0.05, 1e-12);
  double previous = 1.0;
  for (double c = 0.0; c <= 1.0; c += 0.05) {
    EXPECT_LE(adaptive_alpha(c), previous);
    previous = adaptive_alpha(c);
  }
}
