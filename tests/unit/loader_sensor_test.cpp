// The camera a scene file describes: Mitsuba's sensor, film and reconstruction filter (and
// JSON's opt-in filter), and the film's highQualityEdges.
#include <gtest/gtest.h>

#include "emlt/scene/loaders/loader.h"
#include "emlt/scene/scene.h"
#include "support/loader_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::any_contains;
using test::load_and_build_error;
using test::small_json;
using test::small_xml;
using test::write_file;

}  // namespace

// highQualityEdges samples just outside the image in Mitsuba, which changes the border
// pixels under a filter wider than a pixel: approximated there (emlt's border pixels are
// Mitsuba's without it), a note with a box filter, nothing when false.
TEST(Loader, HighQualityEdgesIsApproximatedUnderAWideFilter) {
  const auto dir = test::scratch_dir("high-quality-edges");
  const auto film = [&](const std::string& name, const std::string& edges,
                        const std::string& filter) {
    return load_scene_description(write_file(dir, name,
                                             R"(<scene version="0.6.0">
  <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/>
    <integer name="height" value="8"/><boolean name="highQualityEdges" value=")" +
                                                 edges + R"("/>)" + filter + R"(</film></sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>)"));
  };
  EXPECT_EQ(film("gaussian.xml", "true", "").verdict(), "approximated: 1 item");
  const SceneDescription box = film("box.xml", "true", R"(<rfilter type="box"/>)");
  EXPECT_EQ(box.verdict(), "exact");
  EXPECT_TRUE(any_contains(box.warnings, "'highQualityEdges' changes nothing with a box filter"));
  const SceneDescription off = film("off.xml", "false", "");
  EXPECT_EQ(off.verdict(), "exact");
  EXPECT_TRUE(off.warnings.empty()) << off.warnings.front();
}

TEST(Loader, XmlSensorFilmSamplerAndIntegrator) {
  const auto dir = test::scratch_dir("sensor");
  const std::string xml = write_file(dir, "scene.xml", R"(<scene version="0.6.0">
  <integrator type="bdpt"><integer name="maxDepth" value="7"/></integrator>
  <sensor type="thinlens">
    <float name="fov" value="30"/><string name="fovAxis" value="smaller"/>
    <float name="apertureRadius" value="0.1"/><float name="focusDistance" value="4"/>
    <transform name="toWorld"><lookat origin="1, 2, 3" target="1, 2, 4" up="0, 1, 0"/></transform>
    <sampler type="ldsampler"><integer name="sampleCount" value="64"/></sampler>
    <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="20"/>
      <rfilter type="gaussian"/></film>
  </sensor>
  <emitter type="constant"><spectrum name="radiance" value="0.5"/></emitter>
  <shape type="sphere"><bsdf type="dielectric"><string name="intIOR" value="water"/></bsdf></shape>
</scene>)");
  const SceneDescription desc = load_scene_description(xml);
  EXPECT_EQ(desc.render.integrator, "bdpt");
  EXPECT_EQ(desc.render.said("--max-depth"), "7");
  EXPECT_EQ(desc.render.said("--spp"), "64");
  EXPECT_EQ(desc.camera.width, 40);
  EXPECT_EQ(desc.camera.height, 20);
  EXPECT_FLOAT_EQ(desc.camera.fov_degrees, 30.0f);
  EXPECT_EQ(desc.camera.fov_axis, CameraDesc::FovAxis::Smaller);
  EXPECT_FLOAT_EQ(desc.camera.aperture_radius, 0.1f);
  EXPECT_FLOAT_EQ(desc.camera.focus_distance, 4.0f);
  EXPECT_FLOAT_EQ(desc.camera.to_world[3][2], 3.0f);
  EXPECT_EQ(desc.environment.kind, EnvironmentDesc::Kind::Constant);
  EXPECT_FLOAT_EQ(desc.environment.radiance.y, 0.5f);
  EXPECT_EQ(desc.camera.filter.kind, PixelFilterDesc::Kind::Gaussian);
  EXPECT_FLOAT_EQ(desc.camera.filter.stddev, 0.5f);
  EXPECT_FALSE(any_contains(desc.warnings, "gaussian"));
  const auto scene = Scene::build(desc);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0, 0, -3), Vec3(0, 0, 1)}, hit));
  EXPECT_TRUE(hit.bsdf->has_delta_lobe());  // smooth dielectric
}

TEST(Loader, FilmFilterFollowsMitsubaDefaultsAndJsonOptIn) {
  const auto dir = test::scratch_dir("film-filter");
  // Mitsuba's film filters with a Gaussian unless told otherwise; a box when told so.
  std::string xml = small_xml("");
  const std::string box = write_file(dir, "box.xml", xml);
  xml.replace(xml.find("<rfilter type=\"box\"/>"), std::string("<rfilter type=\"box\"/>").size(),
              "");
  const std::string by_default = write_file(dir, "default.xml", xml);
  EXPECT_EQ(load_scene_description(box).camera.filter.kind, PixelFilterDesc::Kind::Box);
  const SceneDescription gaussian = load_scene_description(by_default);
  EXPECT_EQ(gaussian.camera.filter.kind, PixelFilterDesc::Kind::Gaussian);
  EXPECT_EQ(gaussian.verdict(), "exact");
  // JSON scenes keep the box unless they ask.
  EXPECT_EQ(
      load_scene_description(write_file(dir, "plain.json", small_json("", ""))).camera.filter.kind,
      PixelFilterDesc::Kind::Box);
  const SceneDescription json = load_scene_description(write_file(
      dir, "tent.json", small_json(R"(, "filter": {"type": "tent", "radius": 1.5})", "")));
  EXPECT_EQ(json.camera.filter.kind, PixelFilterDesc::Kind::Tent);
  EXPECT_FLOAT_EQ(json.camera.filter.radius, 1.5f);
  const std::string bad =
      write_file(dir, "bad.json", small_json(R"(, "filter": {"type": "sinc"})", ""));
  EXPECT_NE(load_and_build_error(bad).find("bad.json: camera.filter.type: unknown filter 'sinc'"),
            std::string::npos)
      << load_and_build_error(bad);
}
