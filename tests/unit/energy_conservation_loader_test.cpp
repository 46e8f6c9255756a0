// Mitsuba 0.6's ensureEnergyConservation, read by every BSDF (on by default): a reflectance,
// transmittance or opacity whose largest component exceeds 1 is scaled by 0.99 over that
// maximum, each parameter on its own (phong and ward scale their two reflectances' sum);
// false leaves them as given. The loader does so for diffuse, the dielectrics, conductors,
// plastics and mask, with the verdict exact, and reads the parameter on the wrappers that
// have nothing to scale.
#include <gtest/gtest.h>

#include <string>

#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "support/bsdf_loader_checks.h"
#include "support/test_support.h"

using namespace emlt;

using test::expect_same_bsdf;
using test::subject;

namespace {

SceneDescription load_xml(const std::string& name, const std::string& bsdf) {
  return test::load_bsdf_xml("energy-conservation", name, bsdf);
}

// The tint of a delta BSDF's sampled lobe, seen facing the surface: reflection for u_lobe 0,
// transmission for u_lobe just below 1.
Rgb delta_weight(const Bsdf& bsdf, float u_lobe) {
  const auto s = bsdf.sample({}, Vec3(0.0f, 0.0f, 1.0f), u_lobe, Vec2(0.5f));
  EXPECT_TRUE(s.has_value());
  return s ? s->weight : Rgb(0.0f);
}

}  // namespace

TEST(EnergyConservationLoader, DiffuseReflectanceAboveOneIsScaledUnlessTurnedOff) {
  const SceneDescription scaled = load_xml(
      "diffuse.xml",
      R"(<bsdf type="diffuse" id="subject"><rgb name="reflectance" value="1.5, 0.75, 0.3"/></bsdf>)");
  EXPECT_EQ(scaled.verdict(), "exact");
  expect_same_bsdf(*subject(scaled).bsdf, *make_lambertian(Rgb(0.99f, 0.495f, 0.198f)), "scaled");

  const SceneDescription kept = load_xml("diffuse_kept.xml", R"(
    <bsdf type="diffuse" id="subject"><rgb name="reflectance" value="1.5, 0.75, 0.3"/>
      <boolean name="ensureEnergyConservation" value="false"/></bsdf>)");
  EXPECT_EQ(kept.verdict(), "exact");
  expect_same_bsdf(*subject(kept).bsdf, *make_lambertian(Rgb(1.5f, 0.75f, 0.3f)), "kept");
}

TEST(EnergyConservationLoader, EachParameterIsScaledOnItsOwn) {
  // A dielectric's two tints: the reflectance (maximum 2) scaled, the transmittance left.
  const SceneDescription glass = load_xml("dielectric.xml", R"(
    <bsdf type="dielectric" id="subject"><rgb name="specularReflectance" value="2, 1, 0.5"/>
      <rgb name="specularTransmittance" value="0.8"/></bsdf>)");
  EXPECT_EQ(glass.verdict(), "exact");
  const Rgb reflected = delta_weight(*subject(glass).bsdf, 0.0f);
  EXPECT_NEAR(reflected.x, 0.99f, 1e-5f);
  EXPECT_NEAR(reflected.y, 0.495f, 1e-5f);
  EXPECT_NEAR(reflected.z, 0.2475f, 1e-5f);
  // Radiance through an interface of eta 1.5046 / 1.000277 is compressed by 1 / eta^2.
  const float eta = 1.5046f / 1.000277f;
  EXPECT_NEAR(delta_weight(*subject(glass).bsdf, 0.999f).x, 0.8f / (eta * eta), 1e-5f);

  // A plastic's diffuse part alone exceeds 1: only it is scaled (not the sum, as phong).
  const SceneDescription plastic = load_xml("plastic.xml", R"(
    <bsdf type="plastic" id="subject"><rgb name="diffuseReflectance" value="1.2, 0.6, 0.6"/>
      <rgb name="specularReflectance" value="0.9"/></bsdf>)");
  EXPECT_EQ(plastic.verdict(), "exact");
  expect_same_bsdf(*subject(plastic).bsdf,
                   *make_rough_plastic(make_constant_texture(Rgb(0.0f)),
                                       make_constant_texture(Rgb(0.99f, 0.495f, 0.495f)),
                                       make_constant_texture(Rgb(0.9f)), 1.49f, 1.000277f),
                   "plastic");

  // A conductor's specularReflectance.
  const SceneDescription metal = load_xml("conductor.xml", R"(
    <bsdf type="roughconductor" id="subject"><rgb name="specularReflectance" value="1.1, 1, 0.55"/>
      <float name="alpha" value="0.3"/></bsdf>)");
  EXPECT_EQ(metal.verdict(), "exact");
  const SceneDescription plain = load_xml("conductor_plain.xml", R"(
    <bsdf type="roughconductor" id="subject"><rgb name="specularReflectance" value="0.99, 0.9, 0.495"/>
      <float name="alpha" value="0.3"/></bsdf>)");
  expect_same_bsdf(*subject(metal).bsdf, *subject(plain).bsdf, "roughconductor");
}

TEST(EnergyConservationLoader, MaskOpacityAndWrappers) {
  const SceneDescription mask = load_xml("mask.xml", R"(
    <bsdf type="mask" id="subject"><float name="opacity" value="2"/><bsdf type="diffuse"/></bsdf>)");
  EXPECT_EQ(mask.verdict(), "exact");
  ASSERT_TRUE(subject(mask).opacity);
  EXPECT_NEAR(subject(mask).opacity->eval(Vec2(0.5f)).x, 0.99f, 1e-6f);

  for (const char* wrapper : {"twosided", "bumpmap"}) {
    const std::string texture =
        std::string(wrapper) == "bumpmap" ? R"(<texture type="checkerboard"/>)" : "";
    const SceneDescription read =
        load_xml(std::string(wrapper) + ".xml",
                 std::string(R"(<bsdf id="subject" type=")") + wrapper + R"(">)" + texture +
                     R"(<boolean name="ensureEnergyConservation" value="false"/>
                     <bsdf type="diffuse"/></bsdf>)");
    EXPECT_EQ(read.verdict(), "exact") << wrapper;
  }
}
