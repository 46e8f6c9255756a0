// Mitsuba 0.6's `coating`, `roughcoating` and `normalmap` as the Mitsuba reader reads them:
// every parameter Mitsuba reads, with Mitsuba's defaults, gives the BSDF it means (verdict
// "exact"), and what Mitsuba refuses is refused in one line naming the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
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
  return test::load_bsdf_xml("coating-loader", name, bsdf);
}

std::string xml_error(const std::string& name, const std::string& bsdf) {
  return test::bsdf_xml_error("coating-loader", name, bsdf);
}

const char* kDiffuse =
    R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.4, 0.6"/></bsdf>)";

}  // namespace

TEST(CoatingLoader, CoatingReadsMitsubasParametersAndDefaults) {
  const SceneDescription defaults =
      load_xml("coating_defaults.xml",
               std::string(R"(<bsdf type="coating" id="subject">)") + kDiffuse + "</bsdf>");
  EXPECT_EQ(defaults.verdict(), "exact");
  EXPECT_EQ(subject(defaults).bsdf->name(), "coating");
  const BsdfPtr diffuse = make_lambertian(Rgb(0.2f, 0.4f, 0.6f));
  // bk7 inside, air outside, thickness 1, no absorption, white specular reflectance.
  expect_same_bsdf(*subject(defaults).bsdf, *make_coating(diffuse, 1.5046f, 1.000277f), "defaults");

  const SceneDescription given = load_xml("coating_given.xml", std::string(R"(
    <bsdf type="coating" id="subject"><string name="intIOR" value="water"/>
      <float name="extIOR" value="1.1"/><float name="thickness" value="0.4"/>
      <rgb name="sigmaA" value="0.5, 1, 2"/><rgb name="specularReflectance" value="0.7"/>)") +
                                                                   kDiffuse + "</bsdf>");
  EXPECT_EQ(given.verdict(), "exact");
  expect_same_bsdf(*subject(given).bsdf,
                   *make_coating(diffuse, 1.333f, 1.1f, 0.4f,
                                 make_constant_texture(Rgb(0.5f, 1.0f, 2.0f)), Rgb(0.7f)),
                   "intIOR, extIOR, thickness, sigmaA, specularReflectance");
  // The old reading (the nested BSDF alone) is told apart by the same comparison.
  const Vec3 wo(0.3f, 0.2f, 0.9327379f), wi(-0.5f, 0.1f, 0.8602325f);
  EXPECT_GT(std::abs(subject(given).bsdf->eval({}, wo, wi).x - diffuse->eval({}, wo, wi).x), 0.01f);
}

TEST(CoatingLoader, RoughCoatingReadsMitsubasParametersAndDefaults) {
  const SceneDescription defaults =
      load_xml("rough_defaults.xml",
               std::string(R"(<bsdf type="roughcoating" id="subject">)") + kDiffuse + "</bsdf>");
  EXPECT_EQ(defaults.verdict(), "exact");
  EXPECT_EQ(subject(defaults).bsdf->name(), "roughcoating");
  const BsdfPtr diffuse = make_lambertian(Rgb(0.2f, 0.4f, 0.6f));
  // Beckmann, alpha 0.1.
  expect_same_bsdf(*subject(defaults).bsdf,
                   *make_rough_coating(diffuse, make_constant_texture(Rgb(0.1f))), "defaults");

  const SceneDescription given = load_xml("rough_given.xml", std::string(R"(
    <bsdf type="roughcoating" id="subject"><string name="distribution" value="ggx"/>
      <float name="alpha" value="0.3"/><float name="intIOR" value="1.7"/>
      <float name="thickness" value="2"/><rgb name="sigmaA" value="0.1, 0.2, 0.3"/>
      <boolean name="sampleVisible" value="false"/>)") + kDiffuse +
                                                                 "</bsdf>");
  EXPECT_EQ(given.verdict(), "exact");
  expect_same_bsdf(
      *subject(given).bsdf,
      *make_rough_coating(diffuse, make_constant_texture(Rgb(0.3f)), MicrofacetType::Ggx, 1.7f,
                          1.000277f, 2.0f, make_constant_texture(Rgb(0.1f, 0.2f, 0.3f))),
      "distribution, alpha, intIOR, thickness, sigmaA");

  // A textured roughness and absorption.
  const SceneDescription textured = load_xml("rough_textured.xml", std::string(R"(
    <bsdf type="roughcoating" id="subject"><string name="distribution" value="ggx"/>
      <texture type="checkerboard" name="alpha"><float name="color0" value="0.05"/>
        <float name="color1" value="0.5"/></texture>
      <texture type="checkerboard" name="sigmaA"><float name="color0" value="0.1"/>
        <float name="color1" value="1"/></texture>)") + kDiffuse + "</bsdf>");
  EXPECT_EQ(textured.verdict(), "exact");
  EXPECT_TRUE(subject(textured).textured);
  const BsdfPtr expected = make_rough_coating(
      diffuse, make_checkerboard_texture(Rgb(0.05f), Rgb(0.5f)), MicrofacetType::Ggx, 1.5046f,
      1.000277f, 1.0f, make_checkerboard_texture(Rgb(0.1f), Rgb(1.0f)));
  for (const Vec2 uv : {Vec2(0.1f, 0.1f), Vec2(0.7f, 0.2f)}) {
    BsdfContext ctx;
    ctx.uv = uv;
    expect_same_bsdf(*subject(textured).bsdf, *expected, "textured alpha and sigmaA", ctx);
  }
}

TEST(CoatingLoader, RefusesWhatMitsubaRefuses) {
  const std::string anisotropic =
      xml_error("rough_aniso.xml", std::string(R"(<bsdf type="roughcoating" id="subject">
        <float name="alphaU" value="0.1"/><float name="alphaV" value="0.3"/>)") +
                                       kDiffuse + "</bsdf>");
  EXPECT_NE(anisotropic.find("rough_aniso.xml"), std::string::npos) << anisotropic;
  EXPECT_NE(anisotropic.find("anisotropic"), std::string::npos) << anisotropic;
  // Equal, they are an isotropic alpha to Mitsuba.
  const SceneDescription equal =
      load_xml("rough_equal.xml", std::string(R"(<bsdf type="roughcoating" id="subject">
        <float name="alphaU" value="0.3"/><float name="alphaV" value="0.3"/>)") +
                                      kDiffuse + "</bsdf>");
  EXPECT_EQ(equal.verdict(), "exact");
  const SceneDescription alpha =
      load_xml("rough_alpha.xml", std::string(R"(<bsdf type="roughcoating" id="subject">
        <float name="alpha" value="0.3"/>)") + kDiffuse + "</bsdf>");
  expect_same_bsdf(*subject(equal).bsdf, *subject(alpha).bsdf, "alphaU = alphaV = alpha");
  const std::string same_ior =
      xml_error("same_ior.xml", std::string(R"(<bsdf type="coating" id="subject">
        <float name="intIOR" value="1.3"/><float name="extIOR" value="1.3"/>)") +
                                    kDiffuse + "</bsdf>");
  EXPECT_NE(same_ior.find("must differ"), std::string::npos) << same_ior;
  const std::string no_nested =
      xml_error("no_nested.xml", R"(<bsdf type="coating" id="subject"/>)");
  EXPECT_NE(no_nested.find("nested"), std::string::npos) << no_nested;
  // Mitsuba 0.6 refuses a bitmap normal map without an explicit gamma.
  const std::string no_gamma =
      xml_error("no_gamma.xml", std::string(R"(<bsdf type="normalmap" id="subject">
        <texture type="bitmap"><string name="filename" value="n.png"/></texture>)") +
                                    kDiffuse + "</bsdf>");
  EXPECT_NE(no_gamma.find("gamma"), std::string::npos) << no_gamma;
}

TEST(CoatingLoader, NormalMapWrapsItsNestedBsdf) {
  const SceneDescription given = load_xml("normalmap.xml", std::string(R"(
    <bsdf type="normalmap" id="subject"><texture type="checkerboard">
      <rgb name="color0" value="0.6, 0.45, 0.9"/><rgb name="color1" value="0.5, 0.5, 1"/>
    </texture>)") + kDiffuse + "</bsdf>");
  EXPECT_EQ(given.verdict(), "exact");
  EXPECT_EQ(subject(given).bsdf->name(), "normalmap");
  EXPECT_TRUE(subject(given).bsdf->is_anisotropic());  // its frame follows dp/du
  EXPECT_TRUE(subject(given).textured);
  const BsdfPtr expected =
      make_normal_map(make_lambertian(Rgb(0.2f, 0.4f, 0.6f)),
                      make_checkerboard_texture(Rgb(0.6f, 0.45f, 0.9f), Rgb(0.5f, 0.5f, 1.0f)));
  for (const Vec2 uv : {Vec2(0.1f, 0.1f), Vec2(0.7f, 0.2f)}) {
    BsdfContext ctx;
    ctx.uv = uv;
    expect_same_bsdf(*subject(given).bsdf, *expected, "normal map", ctx);
  }
}
