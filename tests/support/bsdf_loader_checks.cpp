#include "support/bsdf_loader_checks.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "emlt/core/rng.h"
#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

namespace emlt::test {

std::string xml_with_bsdf(const std::string& bsdf) {
  return R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film>
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
  )" + bsdf +
         R"(
  <shape type="sphere"><ref id="subject"/></shape>
</scene>
)";
}

SceneDescription load_bsdf_xml(const std::string& folder, const std::string& name,
                               const std::string& bsdf) {
  return load_scene_description(write_file(scratch_dir(folder), name, xml_with_bsdf(bsdf)));
}

std::string bsdf_xml_error(const std::string& folder, const std::string& name,
                           const std::string& bsdf) {
  const std::string path = write_file(scratch_dir(folder), name, xml_with_bsdf(bsdf));
  return error_of([&] { load_scene_description(path); });
}

std::string json_with_material(const std::string& material) {
  return R"({"camera": {"lookat": {"origin": [0,0,-5], "target": [0,0,0], "up": [0,1,0]}, "fov": 40},
  "materials": {"subject": )" +
         material + R"(},
  "shapes": [{"type": "rectangle", "emission": [1,1,1]}, {"type": "sphere", "material": "subject"}]})";
}

const MaterialDesc& subject(const SceneDescription& description) {
  for (const MaterialDesc& m : description.materials)
    if (m.name == "subject") return m;
  throw std::runtime_error("no material named subject");
}

void expect_same_bsdf(const Bsdf& loaded, const Bsdf& expected, const std::string& what,
                      const BsdfContext& ctx) {
  Rng rng(7, 0);
  for (int n = 0; n < 200; ++n) {
    const Vec3 wo = glm::normalize(Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform()));
    const Vec3 wi = glm::normalize(Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform()));
    const Rgb a = loaded.eval(ctx, wo, wi), b = expected.eval(ctx, wo, wi);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c], b[c], 1e-5f * (1.0f + b[c])) << what;
    ASSERT_NEAR(loaded.pdf(ctx, wo, wi), expected.pdf(ctx, wo, wi),
                1e-5f * (1.0f + expected.pdf(ctx, wo, wi)))
        << what;
  }
}

}  // namespace emlt::test
