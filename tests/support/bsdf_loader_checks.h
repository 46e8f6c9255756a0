#pragma once
// What the tests of the loaders' BSDF readers share: a small scene whose sphere carries the
// material under test (named "subject"), in either format, and a comparison of the BSDF a
// loader made with the one it should have made.
#include <string>

#include "emlt/scene/description.h"
#include "emlt/scene/materials.h"

namespace emlt::test {

// A Mitsuba scene: a light, and a sphere whose BSDF is <ref id="subject"/>; `bsdf` declares it.
std::string xml_with_bsdf(const std::string& bsdf);
// xml_with_bsdf(bsdf) written as `name` into the scratch folder `folder`, loaded; and the
// error its loading gives (empty when it loads).
SceneDescription load_bsdf_xml(const std::string& folder, const std::string& name,
                               const std::string& bsdf);
std::string bsdf_xml_error(const std::string& folder, const std::string& name,
                           const std::string& bsdf);
// A JSON scene: a light, and a sphere whose material is `material` (a JSON object).
std::string json_with_material(const std::string& material);
// The material named "subject" (throws when there is none).
const MaterialDesc& subject(const SceneDescription& description);
// `loaded` and `expected` agree on value and density at 200 random directions.
void expect_same_bsdf(const Bsdf& loaded, const Bsdf& expected, const std::string& what,
                      const BsdfContext& ctx = {});

}  // namespace emlt::test
