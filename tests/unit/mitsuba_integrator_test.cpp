// Which emlt integrator a Mitsuba scene's <integrator> names, and what its Metropolis
// integrators' parameters count as.
#include <gtest/gtest.h>

#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

SceneDescription with_integrator(const std::string& name, const std::string& integrator) {
  const auto dir = test::scratch_dir("mitsuba-integrator");
  return load_scene_description(test::write_file(dir, name, R"(<?xml version="1.0"?>
<scene version="0.6.0">
  )" + integrator + R"(
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>
)"));
}

bool any_contains(const std::vector<std::string>& lines, const std::string& needle) {
  for (const std::string& line : lines)
    if (line.find(needle) != std::string::npos) return true;
  return false;
}

}  // namespace

// Mitsuba's PSSMLT converges to the path tracer's image whichever sampler drives it and
// however often it takes a large step: emlt's pssmlt renders it, and both parameters are
// notes, not items of the verdict.
TEST(MitsubaIntegrator, PssmltIsEmltsPssmltAndItsTuningIsANote) {
  const SceneDescription pss = with_integrator(
      "pssmlt.xml",
      R"(<integrator type="pssmlt"><integer name="maxDepth" value="4"/>
      <boolean name="bidirectional" value="false"/><float name="pLarge" value="0.1"/></integrator>)");
  EXPECT_EQ(pss.render.integrator, "pssmlt");
  EXPECT_EQ(pss.verdict(), "exact");
  EXPECT_EQ(pss.render.said("--max-depth"), "4");
  EXPECT_TRUE(any_contains(pss.warnings, "'bidirectional', 'pLarge' ignored (they change the noise"))
      << (pss.warnings.empty() ? "" : pss.warnings.front());
}

// An integrator emlt does not have falls back to its default and says so: the verdict is
// approximated (stochastic progressive photon mapping converges to the same image, by other
// means).
TEST(MitsubaIntegrator, AnIntegratorEmltLacksFallsBackLoudly) {
  const SceneDescription sppm = with_integrator("sppm.xml", R"(<integrator type="sppm"/>)");
  EXPECT_TRUE(sppm.render.integrator.empty());
  EXPECT_EQ(sppm.verdict(), "approximated: 1 item");
  EXPECT_TRUE(any_contains(sppm.warnings, "integrator type 'sppm' is not supported"));
}

// Mitsuba's ERPT is emlt's: its chain counts, chain length, direct samples (-1: the chains
// take the direct light too), luminance samples, perturbation switches and the manifold
// perturbation's lambda under emlt's flags; every perturbation switched off refused, as
// Mitsuba refuses it.
TEST(MitsubaIntegrator, ErptIsEmltsErptWithItsParameters) {
  const SceneDescription erpt = with_integrator(
      "erpt-params.xml",
      R"(<integrator type="erpt"><integer name="maxDepth" value="5"/>
      <float name="numChains" value="2.5"/><integer name="maxChains" value="4"/>
      <integer name="chainLength" value="50"/><integer name="directSamples" value="-1"/>
      <integer name="luminanceSamples" value="2000"/>
      <boolean name="causticPerturbation" value="false"/>
      <boolean name="manifoldPerturbation" value="true"/><float name="lambda" value="20"/>
      </integrator>)");
  EXPECT_EQ(erpt.render.integrator, "erpt");
  EXPECT_EQ(erpt.verdict(), "exact");
  EXPECT_EQ(erpt.render.said("--max-depth"), "5");
  EXPECT_EQ(std::stod(*erpt.render.said("--erpt-chains")), 2.5);
  EXPECT_EQ(std::stod(*erpt.render.said("--erpt-max-chains")), 4.0);
  EXPECT_EQ(erpt.render.said("--erpt-chain-length"), "50");
  EXPECT_EQ(erpt.render.said("--direct"), "mlt");
  EXPECT_EQ(erpt.render.said("--bootstrap"), "2000");
  EXPECT_EQ(erpt.render.said("--mutations"), "lens=1,multichain=1,manifold=1");
  EXPECT_EQ(erpt.render.said("--manifold-lambda"), "20");

  const SceneDescription plain = with_integrator("erpt.xml", R"(<integrator type="erpt"/>)");
  EXPECT_EQ(plain.render.integrator, "erpt");
  EXPECT_EQ(plain.verdict(), "exact");
  EXPECT_EQ(plain.render.said("--mutations"), "lens=1,caustic=1,multichain=1");
  EXPECT_FALSE(plain.render.said("--erpt-chains").has_value());

  // A value the flag would refuse is refused in the file, naming it and the parameter.
  const std::string bad = test::error_of([&] {
    with_integrator("erpt-bad.xml", R"(<integrator type="erpt"><float name="numChains" value="0"/>
      </integrator>)");
  });
  EXPECT_NE(bad.find("erpt-bad.xml"), std::string::npos) << bad;
  EXPECT_NE(bad.find("numChains"), std::string::npos) << bad;
  EXPECT_NE(bad.find("a positive number"), std::string::npos) << bad;
  // Small counts keep their digits (a fixed six decimals would read 1e-7 as 0).
  EXPECT_EQ(std::stod(*with_integrator("erpt-small.xml", R"(<integrator type="erpt">
      <float name="numChains" value="1e-7"/></integrator>)")
                           .render.said("--erpt-chains")),
            double(1e-7f));

  EXPECT_THROW(with_integrator("erpt-none.xml", R"(<integrator type="erpt">
      <boolean name="lensPerturbation" value="false"/>
      <boolean name="causticPerturbation" value="false"/>
      <boolean name="multiChainPerturbation" value="false"/></integrator>)"),
               std::exception);
}

// Mitsuba's mlt with the manifold perturbation is manifold exploration: emlt's memlt with
// the strategies the file switches on (Mitsuba's defaults: Veach's set and the manifold
// perturbation) and its lambda; without it, mlt with its own mix.
TEST(MitsubaIntegrator, MltWithTheManifoldPerturbationIsMemlt) {
  const SceneDescription memlt = with_integrator(
      "memlt.xml", R"(<integrator type="mlt"><boolean name="manifoldPerturbation" value="true"/>
      <boolean name="lensPerturbation" value="false"/><float name="probFactor" value="30"/>
      </integrator>)");
  EXPECT_EQ(memlt.render.integrator, "memlt");
  EXPECT_EQ(memlt.verdict(), "exact");
  EXPECT_EQ(memlt.render.said("--mutations"), "bidir=1,caustic=1,multichain=1,manifold=1");
  EXPECT_EQ(memlt.render.said("--manifold-lambda"), "30");
  const SceneDescription mlt = with_integrator(
      "mlt.xml", R"(<integrator type="mlt"><float name="lambda" value="30"/></integrator>)");
  EXPECT_EQ(mlt.render.integrator, "mlt");
  EXPECT_EQ(mlt.verdict(), "exact");
  EXPECT_FALSE(mlt.render.said("--mutations").has_value());
  EXPECT_FALSE(mlt.render.said("--manifold-lambda").has_value());
  const std::string bad = test::error_of([&] {
    with_integrator("memlt-bad.xml", R"(<integrator type="mlt">
      <boolean name="manifoldPerturbation" value="true"/><float name="lambda" value="-1"/>
      </integrator>)");
  });
  EXPECT_NE(bad.find("memlt-bad.xml"), std::string::npos) << bad;
  EXPECT_NE(bad.find("lambda"), std::string::npos) << bad;
}

// ERPT's avgAngleChangeSurface fixes the offset manifolds' microfacet turn; its default 0
// (Mitsuba measures it while rendering) leaves emlt's fixed guess.
TEST(MitsubaIntegrator, ErptAngleChangeSetsTheOffsetManifoldsTurn) {
  const SceneDescription fixed = with_integrator(
      "erpt-angle.xml", R"(<integrator type="erpt"><boolean name="manifoldPerturbation" value="true"/>
      <float name="avgAngleChangeSurface" value="2.5"/></integrator>)");
  EXPECT_EQ(fixed.render.said("--manifold-angle-change"), "2.5");
  EXPECT_EQ(fixed.verdict(), "exact");
  const SceneDescription measured = with_integrator(
      "erpt-angle-0.xml", R"(<integrator type="erpt"><boolean name="manifoldPerturbation" value="true"/>
      <float name="avgAngleChangeSurface" value="0"/></integrator>)");
  EXPECT_FALSE(measured.render.said("--manifold-angle-change").has_value());
  const std::string bad = test::error_of([&] {
    with_integrator("erpt-angle-bad.xml", R"(<integrator type="erpt">
      <float name="avgAngleChangeSurface" value="120"/></integrator>)");
  });
  EXPECT_NE(bad.find("erpt-angle-bad.xml"), std::string::npos) << bad;
  EXPECT_NE(bad.find("avgAngleChangeSurface"), std::string::npos) << bad;
}

// The rest of PSSMLT's tuning, and bdpt's strategy images, change no render either.
TEST(MitsubaIntegrator, PssmltTuningAndBdptStrategyImagesKeepTheVerdictExact) {
  const SceneDescription pss = with_integrator(
      "pssmlt-tuning.xml",
      R"(<integrator type="pssmlt"><boolean name="kelemenStyleWeights" value="false"/>
      <boolean name="directSampling" value="false"/><float name="mutationSizeLow" value="0.001"/>
      <float name="mutationSizeHigh" value="0.02"/></integrator>)");
  EXPECT_EQ(pss.verdict(), "exact");
  const SceneDescription bdpt = with_integrator(
      "bdpt-weighted.xml",
      R"(<integrator type="bdpt"><boolean name="showWeighted" value="true"/></integrator>)");
  EXPECT_EQ(bdpt.verdict(), "exact");
  EXPECT_TRUE(any_contains(bdpt.warnings, "'showWeighted': the strategies' own images are not written"));
}
