// Primary-sample-space MLT (Kelemen) and Multiplexed MLT (Hachisuka) against exact answers
// and against BDPT, with the classic mistakes injected (integrators/pss/pss_integrator.h).
//
// The closed emissive box with a coloured albedo gives the exact colour of every path
// length (mlt_test.cpp explains why its colour records how the chains weigh lengths); the
// Cornell box checks the image's shape against the path tracer.
#include <gtest/gtest.h>

#include <cstring>

#include "emlt/integrators/bdpt.h"
#include "emlt/integrators/path_tracer.h"
#include "emlt/integrators/pss/pss_integrator.h"
#include "emlt/scene/loaders/loader.h"
#include "support/mlt_test_helpers.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

const Rgb kAlbedo(0.9f, 0.5f, 0.1f);

enum class Variant { PssPt, PssBdpt, Mmlt };
const char* variant_name(Variant v) {
  return v == Variant::PssPt ? "pssmlt-pt" : v == Variant::PssBdpt ? "pssmlt-bdpt" : "mmlt";
}

RenderSettings pss_settings(Variant v, int max_depth, bool direct_separate) {
  RenderSettings s;
  s.progress = false;
  s.max_depth = max_depth;
  s.direct_separate = direct_separate;
  s.pss_bdpt = v == Variant::PssBdpt;
  // 16x16 image: 256k mutations; BDPT's samples cost about three path tracer ones.
  s.mutations_per_pixel = v == Variant::PssBdpt ? 400 : 1000;
  s.bootstrap_samples = 20000;
  s.chains = 64;
  s.direct_spp = 256;
  s.threads = 2;
  return s;
}

Image render_pss(Variant v, const Scene& scene, const RenderSettings& s, PssOptions options = {}) {
  options.multiplexed = v == Variant::Mmlt;
  ProgressReporter progress(false);
  return PssMltIntegrator(options).render(scene, s, progress).image;
}

DVec3 mean_of(const Image& image) {
  DVec3 sum(0.0);
  for (const Rgb& p : image.pixels) sum += DVec3(p);
  return sum / double(image.pixels.size());
}

Rgb relative_error(const Image& image, const Rgb& exact) {
  const DVec3 mean = mean_of(image);
  return Rgb(float(mean.x / exact.x - 1.0), float(mean.y / exact.y - 1.0),
             float(mean.z / exact.z - 1.0));
}

float worst(const Rgb& e) {
  return std::max({std::abs(e.x), std::abs(e.y), std::abs(e.z)});
}

std::unique_ptr<Scene> cornell(int size) {
  SceneDescription d =
      load_scene_description(test::source_path("scenes/cornell-box/scene.json"), {});
  d.camera.width = d.camera.height = size;
  return Scene::build(std::move(d));
}

// The Cornell box at 24 x 24 by the path tracer (4x faster than BDPT here, and as
// accurate over 8 x 8 tiles), computed once per test process.
const Image& cornell_reference() {
  static const Image reference = [] {
    RenderSettings r;
    r.progress = false;
    r.spp = 1024;
    r.threads = 2;
    ProgressReporter progress(false);
    return PathTracer().render(*cornell(24), r, progress).image;
  }();
  return reference;
}

// Luminance over 3 x 3 tiles of the Cornell box against the reference: the worst tile's relative
// deviation (after the images' total ratio), and that ratio.
std::pair<double, double> cornell_deviation(const Image& image) {
  const test::TileDeviation d = test::tile_deviation(image, cornell_reference(), 3);
  return {d.worst, d.scale};
}

RenderSettings cornell_settings(Variant v) {
  RenderSettings s = pss_settings(v, -1, true);
  s.mutations_per_pixel = v == Variant::PssBdpt ? 300 : 600;
  s.chains = 256;
  s.direct_spp = 1024;
  return s;
}

}  // namespace

class PssClosedBox : public ::testing::TestWithParam<std::tuple<Variant, bool>> {};

TEST_P(PssClosedBox, ChainsReproduceTheExactColour) {
  const auto [variant, direct_separate] = GetParam();
  const int max_depth = 5;
  const auto scene = test::emissive_box(kAlbedo, 1.0f);
  const Rgb exact = test::emissive_box_radiance(kAlbedo, 1.0f, max_depth);
  const Rgb e = relative_error(
      render_pss(variant, *scene, pss_settings(variant, max_depth, direct_separate)), exact);
  std::printf("[ info     ] %s direct %d: error %.4f %.4f %.4f\n", variant_name(variant),
              int(direct_separate), e.x, e.y, e.z);
  EXPECT_LT(worst(e), 0.02);
}

INSTANTIATE_TEST_SUITE_P(TracersAndDirect, PssClosedBox,
                         ::testing::Combine(::testing::Values(Variant::PssPt, Variant::PssBdpt,
                                                              Variant::Mmlt),
                                            ::testing::Bool()));

class PssCornellBox : public ::testing::TestWithParam<Variant> {};

TEST_P(PssCornellBox, ConvergesToThePathTracer) {
  const Variant variant = GetParam();
  const auto [deviation, scale] =
      cornell_deviation(render_pss(variant, *cornell(24), cornell_settings(variant)));
  std::printf("[ info     ] %s: total ratio %.4f, worst tile %.4f\n", variant_name(variant), scale,
              deviation);
  EXPECT_NEAR(scale, 1.0, 0.02);
  EXPECT_LT(deviation, 0.05);
}

INSTANTIATE_TEST_SUITE_P(Tracers, PssCornellBox,
                         ::testing::Values(Variant::PssPt, Variant::PssBdpt, Variant::Mmlt));

// The Cornell-box test above catches a wrong Metropolis acceptance ratio (min(1, sqrt(f'/f))
// was tried) for pssmlt over the path tracer and for mmlt, but not for pssmlt over BDPT, whose
// image at the default large-step probability 0.3 leans on the large steps' own
// acceptance-free share. With large steps at 0.02 the image comes almost wholly from the
// chains, and that ratio shows (worst tile 0.090 against 0.030 correct). The closed box cannot
// show it: its paths of one length all have the same contribution.
TEST(PssMostlySmallSteps, BdptChainsConvergeToThePathTracer) {
  RenderSettings s = cornell_settings(Variant::PssBdpt);
  s.large_step_probability = 0.02;
  s.mutations_per_pixel = 900;
  const auto [deviation, scale] = cornell_deviation(render_pss(Variant::PssBdpt, *cornell(24), s));
  std::printf("[ info     ] pssmlt-bdpt, large steps 0.02: total ratio %.4f, worst tile %.4f\n",
              scale, deviation);
  EXPECT_NEAR(scale, 1.0, 0.02);
  EXPECT_LT(deviation, 0.05);
}

TEST(PssInjectedBugs, DroppedLargeStepWeightDarkensTheImage) {
  // Without the large steps' own share (a + 1 -> a), the estimator loses
  // p_L / (f*/b + p_L) of the image.
  const auto scene = test::emissive_box(kAlbedo, 1.0f);
  const Rgb exact = test::emissive_box_radiance(kAlbedo, 1.0f, 5);
  PssOptions bug;
  bug.drop_large_step_weight = true;
  for (Variant v : {Variant::PssPt, Variant::Mmlt}) {
    const Rgb e = relative_error(render_pss(v, *scene, pss_settings(v, 5, false), bug), exact);
    std::printf("[ info     ] %s: error %.4f %.4f %.4f\n", variant_name(v), e.x, e.y, e.z);
    EXPECT_GT(worst(e), 0.1) << variant_name(v);
  }
}

TEST(PssInjectedBugs, CoordinateNotRestoredOnRejectionDistortsTheImage) {
  PssOptions bug;
  bug.keep_coordinate_on_reject = true;
  const auto [deviation, scale] = cornell_deviation(
      render_pss(Variant::PssPt, *cornell(24), cornell_settings(Variant::PssPt), bug));
  std::printf("[ info     ] total ratio %.4f, worst tile %.4f\n", scale, deviation);
  EXPECT_TRUE(deviation > 0.08 || std::abs(scale - 1.0) > 0.05) << deviation << " " << scale;
}

TEST(PssInjectedBugs, MmltWithoutTechniqueSelectionProbabilityIsWrong) {
  const auto scene = test::emissive_box(kAlbedo, 1.0f);
  const Rgb exact = test::emissive_box_radiance(kAlbedo, 1.0f, 5);
  PssOptions bug;
  bug.ignore_technique_selection = true;
  const Rgb e = relative_error(
      render_pss(Variant::Mmlt, *scene, pss_settings(Variant::Mmlt, 5, false), bug), exact);
  std::printf("[ info     ] error %.4f %.4f %.4f\n", e.x, e.y, e.z);
  EXPECT_GT(worst(e), 0.1);
}

class PssDeterminism : public ::testing::TestWithParam<Variant> {};

TEST_P(PssDeterminism, SameBitsOnOneTwoAndTwentyThreads) {
  const auto scene = cornell(16);
  RenderSettings s = pss_settings(GetParam(), -1, true);
  s.mutations_per_pixel = 40;
  s.chains = 0;  // the default count (chosen from the budget, not the threads)
  const auto bits_of = [&](int threads, uint64_t seed) {
    s.threads = threads;
    s.seed = seed;
    return render_pss(GetParam(), *scene, s);
  };
  const Image one = bits_of(1, 1), two = bits_of(2, 1), twenty = bits_of(20, 1),
              other = bits_of(2, 2);
  const size_t bytes = one.pixels.size() * sizeof(Rgb);
  EXPECT_EQ(0, std::memcmp(one.pixels.data(), two.pixels.data(), bytes));
  EXPECT_EQ(0, std::memcmp(one.pixels.data(), twenty.pixels.data(), bytes));
  EXPECT_NE(0, std::memcmp(one.pixels.data(), other.pixels.data(), bytes));
}

INSTANTIATE_TEST_SUITE_P(Tracers, PssDeterminism,
                         ::testing::Values(Variant::PssPt, Variant::PssBdpt, Variant::Mmlt));
