// The normalisation drawn beside the chains (normalisation_pass.h): the bootstrap's estimator
// numbered on from its last sample, the same sums however it is sliced, threaded or stopped,
// and on a scene whose light arrives mostly by rare, bright paths an error that covers b's
// spread over seeds once enough samples are drawn, which the bootstrap's alone does not.
#include "emlt/integrators/mlt/normalisation_pass.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/mlt/bootstrap.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "support/mlt_test_helpers.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

BootstrapParams params(uint64_t seed, int samples, int threads) {
  BootstrapParams p;
  p.seed = seed;
  p.samples = samples;
  p.max_edges = 8;
  p.threads = threads;
  return p;
}

bool same_sums(const NormalisationSums& a, const NormalisationSums& b) {
  return a.samples == b.samples && a.sum == b.sum && a.sum_squares == b.sum_squares &&
         a.largest == b.largest;
}

}  // namespace

// The pass's samples are the bootstrap's next ones: a pass of M samples after a bootstrap of
// N sums what a bootstrap of N + M samples sums (but for rounding: other groups). With the
// pass numbering its samples from 0 again (injected: it would count the bootstrap's paths
// twice) the sums differ.
TEST(NormalisationPass, DrawsTheBootstrapsNextSamples) {
  const auto scene = test::shipped_scene("cornell-box", 16);
  const BootstrapParams p = params(7, 3000, 2);
  const Bootstrap bootstrap = run_bootstrap(*scene, p);
  NormalisationPass pass(*scene, p, 1.0);
  pass.start(bootstrap);
  EXPECT_EQ(pass.sums().b(), bootstrap.b);  // nothing drawn yet: the bootstrap's b, to the bit
  ASSERT_TRUE(pass.up_to(5000));            // 5,000 mutations at rate 1: 5 groups of 1024
  EXPECT_EQ(pass.drawn(), uint64_t(5 * NormalisationPass::kGroup));
  EXPECT_EQ(pass.sums().samples, uint64_t(3000 + 5120));

  BootstrapParams whole = p;
  whole.samples = 3000 + 5120;
  const Bootstrap all = run_bootstrap(*scene, whole);
  EXPECT_NEAR(pass.sums().sum, all.sum, 1e-12 * all.sum);
  EXPECT_NEAR(pass.sums().sum_squares, all.sum_squares, 1e-12 * all.sum_squares);
  EXPECT_EQ(pass.sums().largest, all.largest_sample);
  EXPECT_NEAR(pass.sums().standard_error(), all.standard_error, 1e-9 * all.standard_error);

  // The injected bug: the pass's samples numbered from 0 are the bootstrap's own.
  NormalisationPass from_zero(*scene, p, 1.0);
  Bootstrap empty;
  empty.samples = 0;
  from_zero.start(empty);
  ASSERT_TRUE(from_zero.up_to(5000));
  double twice = bootstrap.sum + from_zero.sums().sum;
  EXPECT_GT(std::abs(twice - all.sum), 1e-6 * all.sum);
}

// Slices end on whole groups, which are summed in order: one slice or many, one thread or
// several, the same bits; a rate of 0 draws nothing and keeps the bootstrap's b.
TEST(NormalisationPass, SameBitsHoweverSlicedOrThreaded) {
  const auto scene = test::shipped_scene("cornell-box", 16);
  const Bootstrap bootstrap = run_bootstrap(*scene, params(3, 2000, 1));
  NormalisationPass once(*scene, params(3, 2000, 1), 0.5);
  once.start(bootstrap);
  ASSERT_TRUE(once.up_to(40000));
  NormalisationPass sliced(*scene, params(3, 2000, 3), 0.5);
  sliced.start(bootstrap);
  for (uint64_t mutations : {1u, 1500u, 9000u, 9001u, 22222u, 40000u})
    ASSERT_TRUE(sliced.up_to(mutations));
  EXPECT_TRUE(same_sums(once.sums(), sliced.sums()));
  EXPECT_EQ(once.drawn(), uint64_t(20480));
  // Asking for fewer than drawn draws nothing.
  ASSERT_TRUE(sliced.up_to(100));
  EXPECT_TRUE(same_sums(once.sums(), sliced.sums()));

  NormalisationPass none(*scene, params(3, 2000, 1), 0.0);
  none.start(bootstrap);
  ASSERT_TRUE(none.up_to(1000000));
  EXPECT_EQ(none.drawn(), uint64_t(0));
  EXPECT_EQ(none.sums().b(), bootstrap.b);
  EXPECT_EQ(none.sums().standard_error(), bootstrap.standard_error);
}

// A checkpoint's figures read back to the same pass; figures no pass can have are refused.
TEST(NormalisationPass, StateRoundTripsAndDamageIsRefused) {
  const auto scene = test::shipped_scene("cornell-box", 16);
  const Bootstrap bootstrap = run_bootstrap(*scene, params(5, 2000, 2));
  NormalisationPass pass(*scene, params(5, 2000, 2), 0.25);
  pass.start(bootstrap);
  ASSERT_TRUE(pass.up_to(10000));
  StateWriter out;
  pass.save(out);
  NormalisationPass loaded(*scene, params(5, 2000, 2), 0.25);
  StateReader in(out.data());
  loaded.load(in);
  EXPECT_TRUE(same_sums(pass.sums(), loaded.sums()));
  EXPECT_EQ(loaded.bootstrap_samples(), uint64_t(2000));
  // Going on from the loaded state is going on from the original.
  ASSERT_TRUE(pass.up_to(30000));
  ASSERT_TRUE(loaded.up_to(30000));
  EXPECT_TRUE(same_sums(pass.sums(), loaded.sums()));

  std::string damaged = out.data();
  // The samples' count (second field) off the group grid.
  uint64_t odd = 2000 + 1000;
  std::memcpy(damaged.data() + sizeof(uint64_t), &odd, sizeof odd);
  NormalisationPass refused(*scene, params(5, 2000, 2), 0.25);
  StateReader bad(damaged);
  EXPECT_THROW(refused.load(bad), StateError);
}

// Split by length (mmlt's b_k): each length's sums are those of the same samples' weights of
// that length, their sum over the lengths the whole sums', and b's sums the counted lengths'.
// The bootstrap's pool split by sample and length sums what the pass draws for the same
// sample numbers (injected: a strategy's length taken as s + t segments, one too many, puts
// each sample's weights in the next length: the pool's split and the drawn one then differ).
// Sliced, threaded or saved and loaded, the same bits.
TEST(NormalisationPass, SplitByLengthSumsEachLengthOfTheSameSamples) {
  const auto scene = test::shipped_scene("cornell-box", 16);
  const BootstrapParams p = params(7, 3 * int(NormalisationPass::kGroup), 2);
  const Bootstrap bootstrap = run_bootstrap(*scene, p);
  std::vector<bool> counted(size_t(p.max_edges - p.min_edges + 1), true);
  counted[2] = false;
  NormalisationPass split(*scene, p, 1.0);
  split.split_by_length(counted);
  split.start(bootstrap);
  ASSERT_TRUE(split.up_to(5000));
  NormalisationPass whole(*scene, p, 1.0);
  whole.start(bootstrap);
  ASSERT_TRUE(whole.up_to(5000));
  ASSERT_EQ(split.lengths().size(), counted.size());
  double all = 0.0, counted_sum = 0.0;
  for (size_t k = 0; k < counted.size(); ++k) {
    EXPECT_EQ(split.lengths()[k].samples, whole.sums().samples);
    all += split.lengths()[k].sum;
    if (counted[k]) counted_sum += split.lengths()[k].sum;
  }
  EXPECT_NEAR(all, whole.sums().sum, 1e-12 * whole.sums().sum);
  EXPECT_NEAR(split.sums().sum, counted_sum, 1e-12 * counted_sum);
  EXPECT_LT(split.sums().sum, 0.999 * all);  // the uncounted length carries light
  EXPECT_EQ(split.sums().samples, whole.sums().samples);

  // The bootstrap's pool, split, against the same samples drawn by the pass.
  NormalisationPass drawn(*scene, p, 1.0);
  drawn.split_by_length(counted);
  Bootstrap empty;
  drawn.start(empty);
  ASSERT_TRUE(drawn.up_to(uint64_t(p.samples)));
  NormalisationPass pooled(*scene, p, 1.0);
  pooled.split_by_length(counted);
  pooled.start(bootstrap);
  for (size_t k = 0; k < counted.size(); ++k) {
    const NormalisationSums &a = drawn.lengths()[k], &b = pooled.lengths()[k];
    EXPECT_EQ(a.samples, b.samples);
    EXPECT_NEAR(a.sum, b.sum, 1e-12 * std::max(a.sum, 1e-30)) << "length index " << k;
    EXPECT_NEAR(a.sum_squares, b.sum_squares, 1e-12 * std::max(a.sum_squares, 1e-30));
    EXPECT_EQ(a.largest, b.largest);
  }
  EXPECT_NEAR(drawn.sums().sum, pooled.sums().sum, 1e-12 * pooled.sums().sum);

  // Sliced over three threads, then saved and loaded: the same bits.
  NormalisationPass sliced(*scene, params(7, p.samples, 3), 1.0);
  sliced.split_by_length(counted);
  sliced.start(bootstrap);
  for (uint64_t mutations : {1u, 1500u, 3333u, 5000u}) ASSERT_TRUE(sliced.up_to(mutations));
  StateWriter out;
  sliced.save(out);
  NormalisationPass loaded(*scene, p, 1.0);
  loaded.split_by_length(counted);
  StateReader in(out.data());
  loaded.load(in);
  EXPECT_TRUE(same_sums(loaded.sums(), split.sums()));
  for (size_t k = 0; k < counted.size(); ++k)
    EXPECT_TRUE(same_sums(loaded.lengths()[k], split.lengths()[k])) << "length index " << k;
}

namespace {

// Mean z^2 over seeds 100, 101, ... of b on the caustic pool after `drawn` pass samples
// beside a bootstrap of 2,048 (paths of up to `edges` segments), z = (b - b_all) / error, b_all
// the seeds' mean; 1 when the printed errors are honest (the seeds' own mean taken out:
// divided by seeds - 1). Also the largest sample's share of b, over the seeds.
struct Coverage {
  double z2_plain, z2_printed, largest_share, spread;
};
Coverage caustic_pool_coverage(const Scene& scene, int seeds, int edges, uint64_t drawn) {
  std::vector<NormalisationSums> sums;
  double total = 0.0;
  for (int seed = 0; seed < seeds; ++seed) {
    BootstrapParams p = params(100 + uint64_t(seed), 2048, 0);
    p.max_edges = edges;
    NormalisationPass pass(scene, p, 1.0);
    pass.start(run_bootstrap(scene, p));
    EXPECT_TRUE(pass.up_to(drawn));
    sums.push_back(pass.sums());
    total += pass.sums().b();
  }
  const double mean = total / seeds;
  Coverage c{0.0, 0.0, 0.0, 0.0};
  for (const NormalisationSums& s : sums) {
    const double d2 = (s.b() - mean) * (s.b() - mean);
    c.z2_plain += d2 / (s.standard_error() * s.standard_error());
    c.z2_printed += d2 / (s.error() * s.error());
    c.spread += d2;
    c.largest_share = std::max(c.largest_share, s.largest_share());
  }
  c.z2_plain /= seeds - 1;
  c.z2_printed /= seeds - 1;
  c.spread = std::sqrt(c.spread / (seeds - 1)) / mean;
  std::printf(
      "%llu samples: mean z^2 %.2f (plain standard error %.2f), spread %.2g of b, "
      "largest sample up to %.2g of b\n",
      static_cast<unsigned long long>(sums.front().samples), c.z2_printed, c.z2_plain, c.spread,
      c.largest_share);
  return c;
}

}  // namespace

// The caustic pool's water slab lets light reach the floor it covers only through specular
// chains on both sides, which a bootstrap sample finds only by hitting the small ceiling light
// through them: rare, bright paths that carry much of b. With the bootstrap's 2,048 samples
// most seeds miss them and print an error far below their distance from the seeds' mean;
// with the 397,312 samples the pass adds (a render of 25 million mutations at the default
// rate), the printed errors cover the spread. Deterministic (fixed seeds); the margins are
// the sampling spread of a mean z^2 over 16 seeds (about 0.35).
TEST(NormalisationPass, ErrorCoversTheSpreadOverSeedsOnceEnoughSamplesAreDrawn) {
  const auto scene = test::shipped_scene("caustic-pool", 16);
  const Coverage few = caustic_pool_coverage(*scene, 16, 6, 0);
  const Coverage many = caustic_pool_coverage(*scene, 16, 6, 397312);
  EXPECT_GT(few.z2_printed, 5.0);  // the bootstrap alone: errors far too small
  EXPECT_LT(many.z2_printed, 2.2);
  EXPECT_GT(many.z2_printed, 0.4);
  EXPECT_LT(many.spread, 0.25 * few.spread);
  EXPECT_LT(many.largest_share, 0.1 * few.largest_share);
}

// The figures of docs/normalisation.md (32 seeds, paths of up to 8 segments, up to a million
// samples each: about 4 minutes on two cores, so not in the default run):
//   emlt_statistical_tests --gtest_also_run_disabled_tests
//     --gtest_filter=NormalisationPass.DISABLED_ErrorCoverageByCount
TEST(NormalisationPass, DISABLED_ErrorCoverageByCount) {
  const auto scene = test::shipped_scene("caustic-pool", 16);
  std::vector<Coverage> rows;
  for (uint64_t drawn : {0ull, 18432ull, 198656ull, 397312ull, 1046528ull})
    rows.push_back(caustic_pool_coverage(*scene, 32, 8, drawn));
  EXPECT_GT(rows.front().z2_printed, 5.0);
  EXPECT_LT(rows.back().z2_printed, 1.6);  // 31 degrees of freedom: 1 +- 0.25
  EXPECT_GT(rows.back().z2_printed, 0.5);
}
