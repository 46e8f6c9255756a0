// Mitsuba 0.6's analytic BRDFs outside the microfacet family (roughdiffuse, phong, ward,
// difftrans) as the loaders read them: Mitsuba's parameter names, aliases and defaults give
// the material they mean, exactly (verdict "exact"), the JSON names give the same one, and a
// value no BSDF can mean is refused in one line naming the file and the parameter.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "support/bsdf_loader_checks.h"
#include "support/test_support.h"

using namespace emlt;

using test::expect_same_bsdf;
using test::json_with_material;
using test::subject;

namespace {

SceneDescription load_xml(const std::string& name, const std::string& bsdf) {
  return test::load_bsdf_xml("classic-bsdf-loader", name, bsdf);
}

std::string xml_error(const std::string& name, const std::string& bsdf) {
  return test::bsdf_xml_error("classic-bsdf-loader", name, bsdf);
}

void expect_one_line_naming(const std::string& message, const std::string& file,
                            const std::string& problem) {
  EXPECT_NE(message.find(file), std::string::npos) << message;
  EXPECT_NE(message.find(problem), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

}  // namespace

TEST(ClassicBsdfLoader, RoughDiffuseReadsMitsubasParametersAndDefaults) {
  const SceneDescription defaults =
      load_xml("rd_defaults.xml", R"(<bsdf type="roughdiffuse" id="subject"/>)");
  EXPECT_EQ(defaults.verdict(), "exact");
  EXPECT_EQ(subject(defaults).bsdf->name(), "rough_diffuse");
  expect_same_bsdf(*subject(defaults).bsdf, *make_rough_diffuse(Rgb(0.5f), 0.2f), "defaults");

  const SceneDescription given = load_xml("rd_given.xml", R"(<bsdf type="roughdiffuse" id="subject">
    <rgb name="diffuseReflectance" value="0.2, 0.4, 0.6"/><float name="alpha" value="0.8"/>
    <boolean name="useFastApprox" value="true"/></bsdf>)");
  EXPECT_EQ(given.verdict(), "exact");
  EXPECT_EQ(subject(given).bsdf->name(), "rough_diffuse_fast");
  expect_same_bsdf(*subject(given).bsdf, *make_rough_diffuse(Rgb(0.2f, 0.4f, 0.6f), 0.8f, true),
                   "diffuseReflectance, alpha, useFastApprox");

  // Mitsuba scales a reflectance above 1 to 0.99 of its largest component (a note), unless
  // told not to.
  const SceneDescription bright =
      load_xml("rd_bright.xml", R"(<bsdf type="roughdiffuse" id="subject">
    <rgb name="reflectance" value="2, 1, 0.5"/></bsdf>)");
  EXPECT_EQ(bright.verdict(), "exact");
  expect_same_bsdf(*subject(bright).bsdf,
                   *make_rough_diffuse(Rgb(2.0f, 1.0f, 0.5f) * (0.99f / 2.0f), 0.2f), "scaled");
  const SceneDescription kept = load_xml("rd_kept.xml", R"(<bsdf type="roughdiffuse" id="subject">
    <rgb name="reflectance" value="2, 1, 0.5"/><boolean name="ensureEnergyConservation" value="false"/></bsdf>)");
  expect_same_bsdf(*subject(kept).bsdf, *make_rough_diffuse(Rgb(2.0f, 1.0f, 0.5f), 0.2f), "kept");

  expect_one_line_naming(xml_error("rd_negative.xml", R"(<bsdf type="roughdiffuse" id="subject">
    <float name="alpha" value="-0.3"/></bsdf>)"),
                         "rd_negative.xml", "'alpha' of a roughdiffuse must not be negative");
}

TEST(ClassicBsdfLoader, RoughDiffuseInJson) {
  const auto dir = test::scratch_dir("classic-bsdf-loader");
  const SceneDescription d = load_scene_description(test::write_file(
      dir, "rd.json", json_with_material(R"({"type": "roughdiffuse", "reflectance": [0.3, 0.2, 0.1],
        "alpha": 0.6, "use_fast_approx": true, "two_sided": false})")));
  expect_same_bsdf(*subject(d).bsdf, *make_rough_diffuse(Rgb(0.3f, 0.2f, 0.1f), 0.6f, true),
                   "json");
}

TEST(ClassicBsdfLoader, PhongReadsMitsubasParametersAndDefaults) {
  const SceneDescription defaults =
      load_xml("phong_defaults.xml", R"(<bsdf type="phong" id="subject"/>)");
  EXPECT_EQ(defaults.verdict(), "exact");
  EXPECT_EQ(subject(defaults).bsdf->name(), "phong");
  expect_same_bsdf(*subject(defaults).bsdf, *make_phong(30.0f, Rgb(0.2f), Rgb(0.5f)), "defaults");

  const SceneDescription given = load_xml("phong_given.xml", R"(<bsdf type="phong" id="subject">
    <float name="exponent" value="12"/><rgb name="specularReflectance" value="0.3, 0.2, 0.1"/>
    <rgb name="diffuseReflectance" value="0.1, 0.2, 0.4"/></bsdf>)");
  EXPECT_EQ(given.verdict(), "exact");
  expect_same_bsdf(*subject(given).bsdf,
                   *make_phong(12.0f, Rgb(0.3f, 0.2f, 0.1f), Rgb(0.1f, 0.2f, 0.4f)), "given");

  // The two reflectances together are scaled to 0.99 of the largest component of their sum.
  const SceneDescription bright = load_xml("phong_bright.xml", R"(<bsdf type="phong" id="subject">
    <spectrum name="specularReflectance" value="0.6"/><rgb name="diffuseReflectance" value="0.8, 0.5, 0.3"/></bsdf>)");
  EXPECT_EQ(bright.verdict(), "exact");
  const float scale = 0.99f / 1.4f;
  expect_same_bsdf(*subject(bright).bsdf,
                   *make_phong(30.0f, Rgb(0.6f * scale), Rgb(0.8f, 0.5f, 0.3f) * scale), "scaled");

  expect_one_line_naming(xml_error("phong_negative.xml", R"(<bsdf type="phong" id="subject">
    <float name="exponent" value="-2"/></bsdf>)"),
                         "phong_negative.xml", "'exponent' of a phong must not be negative");
}

TEST(ClassicBsdfLoader, PhongInJson) {
  const auto dir = test::scratch_dir("classic-bsdf-loader");
  const SceneDescription d = load_scene_description(test::write_file(
      dir, "phong.json",
      json_with_material(R"({"type": "phong", "exponent": 7, "specular_reflectance": 0.3,
        "diffuse_reflectance": [0.2, 0.1, 0.05], "two_sided": false})")));
  expect_same_bsdf(*subject(d).bsdf, *make_phong(7.0f, Rgb(0.3f), Rgb(0.2f, 0.1f, 0.05f)), "json");
  const std::string path = test::write_file(
      dir, "phong_negative.json", json_with_material(R"({"type": "phong", "exponent": -1})"));
  expect_one_line_naming(test::error_of([&] { load_scene_description(path); }),
                         "phong_negative.json", "exponent: must be >= 0");
}

TEST(ClassicBsdfLoader, WardReadsMitsubasParametersAndDefaults) {
  const SceneDescription defaults =
      load_xml("ward_defaults.xml", R"(<bsdf type="ward" id="subject"/>)");
  EXPECT_EQ(defaults.verdict(), "exact");
  EXPECT_EQ(subject(defaults).bsdf->name(), "ward_balanced");
  EXPECT_FALSE(subject(defaults).bsdf->is_anisotropic());
  expect_same_bsdf(*subject(defaults).bsdf,
                   *make_ward(WardVariant::Balanced, 0.1f, 0.1f, Rgb(0.2f), Rgb(0.5f)), "defaults");

  // `alpha` is the default of whichever of alphaU and alphaV is not given; variant names
  // are read in any case, as Mitsuba reads them.
  const SceneDescription given = load_xml("ward_given.xml", R"(<bsdf type="ward" id="subject">
    <string name="variant" value="Ward-Duer"/><float name="alpha" value="0.3"/><float name="alphaV" value="0.05"/>
    <rgb name="specularReflectance" value="0.3, 0.2, 0.1"/><rgb name="diffuseReflectance" value="0.1, 0.2, 0.4"/></bsdf>)");
  EXPECT_EQ(given.verdict(), "exact");
  EXPECT_TRUE(subject(given).bsdf->is_anisotropic());
  expect_same_bsdf(
      *subject(given).bsdf,
      *make_ward(WardVariant::WardDuer, 0.3f, 0.05f, Rgb(0.3f, 0.2f, 0.1f), Rgb(0.1f, 0.2f, 0.4f)),
      "given");
  EXPECT_EQ(subject(load_xml("ward_original.xml", R"(<bsdf type="ward" id="subject">
    <string name="variant" value="ward"/></bsdf>)"))
                .bsdf->name(),
            "ward_original");

  const SceneDescription bright = load_xml("ward_bright.xml", R"(<bsdf type="ward" id="subject">
    <spectrum name="specularReflectance" value="0.5"/><spectrum name="diffuseReflectance" value="0.75"/></bsdf>)");
  expect_same_bsdf(*subject(bright).bsdf,
                   *make_ward(WardVariant::Balanced, 0.1f, 0.1f, Rgb(0.5f * 0.99f / 1.25f),
                              Rgb(0.75f * 0.99f / 1.25f)),
                   "scaled");

  expect_one_line_naming(xml_error("ward_variant.xml", R"(<bsdf type="ward" id="subject">
    <string name="variant" value="blinn"/></bsdf>)"),
                         "ward_variant.xml",
                         "unknown ward variant 'blinn' (ward, ward-duer or balanced)");
  expect_one_line_naming(xml_error("ward_zero.xml", R"(<bsdf type="ward" id="subject">
    <float name="alphaU" value="0"/></bsdf>)"),
                         "ward_zero.xml", "'alphaU' of a ward must be positive");
  expect_one_line_naming(xml_error("ward_alpha.xml", R"(<bsdf type="ward" id="subject">
    <float name="alpha" value="-1"/></bsdf>)"),
                         "ward_alpha.xml", "'alpha' must be a positive number");
}

TEST(ClassicBsdfLoader, WardInJson) {
  const auto dir = test::scratch_dir("classic-bsdf-loader");
  const SceneDescription d = load_scene_description(test::write_file(
      dir, "ward.json",
      json_with_material(R"({"type": "ward", "variant": "ward-duer", "alpha": 0.2, "alpha_v": 0.4,
        "specular_reflectance": 0.3, "diffuse_reflectance": [0.2, 0.1, 0.05], "two_sided": false})")));
  expect_same_bsdf(*subject(d).bsdf,
                   *make_ward(WardVariant::WardDuer, 0.2f, 0.4f, Rgb(0.3f), Rgb(0.2f, 0.1f, 0.05f)),
                   "json");
  const std::string path = test::write_file(
      dir, "ward_variant.json", json_with_material(R"({"type": "ward", "variant": "blinn"})"));
  expect_one_line_naming(test::error_of([&] { load_scene_description(path); }), "ward_variant.json",
                         "variant: expected \"ward\", \"ward-duer\" or \"balanced\"");
}

TEST(ClassicBsdfLoader, DiffuseTransmitterReadsMitsubasParametersAndDefaults) {
  const SceneDescription defaults =
      load_xml("difftrans_defaults.xml", R"(<bsdf type="difftrans" id="subject"/>)");
  EXPECT_EQ(defaults.verdict(), "exact");
  EXPECT_EQ(subject(defaults).bsdf->name(), "diffuse_transmitter");
  expect_same_bsdf(*subject(defaults).bsdf, *make_diffuse_transmitter(Rgb(0.5f)), "defaults");
  const SceneDescription alias =
      load_xml("difftrans_alias.xml", R"(<bsdf type="difftrans" id="subject">
    <rgb name="diffuseTransmittance" value="0.2, 0.4, 0.8"/></bsdf>)");
  EXPECT_EQ(alias.verdict(), "exact");
  expect_same_bsdf(*subject(alias).bsdf, *make_diffuse_transmitter(Rgb(0.2f, 0.4f, 0.8f)),
                   "diffuseTransmittance");
  const SceneDescription bright =
      load_xml("difftrans_bright.xml", R"(<bsdf type="difftrans" id="subject">
    <rgb name="transmittance" value="1.5, 1, 0.5"/></bsdf>)");
  expect_same_bsdf(*subject(bright).bsdf,
                   *make_diffuse_transmitter(Rgb(1.5f, 1.0f, 0.5f) * (0.99f / 1.5f)), "scaled");
}

TEST(ClassicBsdfLoader, DiffuseTransmitterInJsonIsNotMadeTwoSided) {
  const auto dir = test::scratch_dir("classic-bsdf-loader");
  const SceneDescription d = load_scene_description(test::write_file(
      dir, "difftrans.json",
      json_with_material(R"({"type": "difftrans", "transmittance": [0.3, 0.2, 0.1]})")));
  EXPECT_EQ(subject(d).bsdf->name(), "diffuse_transmitter");
  expect_same_bsdf(*subject(d).bsdf, *make_diffuse_transmitter(Rgb(0.3f, 0.2f, 0.1f)), "json");
}

// A textured reflectance above 1 is not scaled (its largest texel is Mitsuba's to know): the
// scene is said to be approximated, naming ensureEnergyConservation.
TEST(ClassicBsdfLoader, TexturedReflectanceAboveOneIsReportedNotScaled) {
  const SceneDescription d = load_xml("textured_bright.xml", R"(<bsdf type="phong" id="subject">
    <texture type="checkerboard" name="diffuseReflectance"><spectrum name="color0" value="0.9"/>
    <spectrum name="color1" value="0.2"/></texture></bsdf>)");
  EXPECT_EQ(d.verdict(), "approximated: 1 item");
  bool named = false;
  for (const std::string& w : d.warnings)
    named |= w.find("ensureEnergyConservation") != std::string::npos;
  EXPECT_TRUE(named);
  const SceneDescription dim = load_xml("textured_dim.xml", R"(<bsdf type="phong" id="subject">
    <texture type="checkerboard" name="diffuseReflectance"><spectrum name="color0" value="0.7"/>
    <spectrum name="color1" value="0.2"/></texture></bsdf>)");
  EXPECT_EQ(dim.verdict(), "exact");
}
