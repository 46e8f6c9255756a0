// Mitsuba 0.6 reads specularReflectance and specularTransmittance of dielectric,
// roughdielectric and thindielectric as a number or a texture. The loader gives a texture
// to the BSDF, verdict exact, and the BSDF tints by its value at the point: between the two
// colours of a checkerboard the response changes by their ratio. Mitsuba's coating and
// roughcoating refuse a textured specularReflectance, and so does the loader.
#include <gtest/gtest.h>

#include <string>

#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/materials.h"
#include "support/bsdf_loader_checks.h"
#include "support/test_support.h"

using namespace emlt;

using test::subject;

namespace {

// A checkerboard of two colours, named `name` inside its BSDF.
std::string checker(const std::string& name) {
  return R"(<texture type="checkerboard" name=")" + name + R"(">
    <rgb name="color0" value="1, 0.5, 0.25"/><rgb name="color1" value="0.1, 0.2, 0.3"/></texture>)";
}

// The BSDF's response at uv: a delta lobe's sampled weight (u_lobe picks the lobe), or the
// value between two fixed directions.
Rgb response(const Bsdf& bsdf, const Vec2& uv, bool delta, float u_lobe) {
  BsdfContext ctx;
  ctx.uv = uv;
  const Vec3 wo = glm::normalize(Vec3(0.2f, 0.1f, 1.0f));
  if (!delta) return bsdf.eval(ctx, wo, glm::normalize(Vec3(-0.25f, -0.1f, 1.0f)));
  const auto s = bsdf.sample(ctx, wo, u_lobe, Vec2(0.5f));
  EXPECT_TRUE(s.has_value());
  return s ? s->weight : Rgb(0.0f);
}

// The response at two points of different cells differs by the ratio of the two colours.
void expect_tinted_by_checker(const std::string& name, const std::string& bsdf, bool delta,
                              float u_lobe = 0.0f) {
  const SceneDescription loaded = test::load_bsdf_xml("specular-tint", name + ".xml", bsdf);
  EXPECT_EQ(loaded.verdict(), "exact") << name;
  const Bsdf& b = *subject(loaded).bsdf;
  const Rgb a = response(b, Vec2(0.25f, 0.25f), delta, u_lobe);
  const Rgb c = response(b, Vec2(0.75f, 0.25f), delta, u_lobe);
  ASSERT_GT(c.x, 0.0f) << name;
  const Rgb ratio = a / c, forward(10.0f, 2.5f, 0.25f / 0.3f);
  const Rgb expected = std::abs(ratio.x - forward.x) < std::abs(ratio.x - 1.0f / forward.x)
                           ? forward
                           : Rgb(1.0f) / forward;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(ratio[k], expected[k], 1e-3f * expected[k]) << name;
}

}  // namespace

TEST(SpecularTintTextureLoader, DielectricsTintByTheTextureAtThePoint) {
  expect_tinted_by_checker(
      "dielectric-reflectance",
      R"(<bsdf type="dielectric" id="subject">)" + checker("specularReflectance") + "</bsdf>", true,
      0.0f);
  expect_tinted_by_checker(
      "dielectric-transmittance",
      R"(<bsdf type="dielectric" id="subject">)" + checker("specularTransmittance") + "</bsdf>",
      true, 0.999f);
  expect_tinted_by_checker(
      "thindielectric",
      R"(<bsdf type="thindielectric" id="subject">)" + checker("specularReflectance") + "</bsdf>",
      true, 0.0f);
  expect_tinted_by_checker("roughdielectric",
                           R"(<bsdf type="roughdielectric" id="subject">
                               <float name="alpha" value="0.3"/>)" +
                               checker("specularReflectance") + "</bsdf>",
                           false);
}

TEST(SpecularTintTextureLoader, CoatingsRefuseATextureAsMitsubaDoes) {
  const std::string black = R"(<bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>)";
  for (const char* type : {"coating", "roughcoating"}) {
    const std::string error =
        test::bsdf_xml_error("specular-tint", std::string(type) + ".xml",
                             std::string(R"(<bsdf id="subject" type=")") + type + R"(">)" +
                                 checker("specularReflectance") + black + "</bsdf>");
    EXPECT_NE(error.find(std::string("the 'specularReflectance' of a ") + type +
                         " must be a colour (Mitsuba refuses a texture for it)"),
              std::string::npos)
        << error;
  }
}
