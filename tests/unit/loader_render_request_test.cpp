// What a scene file says about rendering: its integrator and that integrator's parameters
// (hideEmitters, strictNormals, the particle tracer's flags), and nothing it does not say.
#include <gtest/gtest.h>

#include "emlt/integrators/registry.h"
#include "emlt/run/integrator.h"
#include "emlt/run/scene_settings.h"
#include "emlt/scene/loaders/loader.h"
#include "support/loader_scenes.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::any_contains;
using test::small_json;
using test::small_xml;
using test::write_file;

}  // namespace

// Mitsuba's hideEmitters (and JSON's hide_emitters) reach the render settings, with no
// warning: every integrator honours it (the conformance scenes light-hide-emitters*).
TEST(Loader, HideEmittersIsASetting) {
  const auto dir = test::scratch_dir("hide-emitters");
  const SceneDescription xml = load_scene_description(write_file(dir, "hide.xml", small_xml(R"(
  <integrator type="path"><boolean name="hideEmitters" value="true"/></integrator>)")));
  EXPECT_EQ(xml.render.said("--hide-emitters"), "true");
  EXPECT_TRUE(xml.warnings.empty());
  EXPECT_FALSE(load_scene_description(write_file(dir, "show.xml", small_xml("")))
                   .render.said("--hide-emitters") == "true");
  std::string json = small_json("", "");
  json.insert(1, R"("integrator": {"type": "pt", "hide_emitters": true}, )");
  EXPECT_TRUE(
      load_scene_description(write_file(dir, "hide.json", json)).render.said("--hide-emitters") ==
      "true");
}

// Mitsuba's particle tracer is emlt's, with its depth parameters; granularity (the light
// paths of a work unit) only schedules the work.
TEST(Loader, XmlParticleTracer) {
  const auto dir = test::scratch_dir("ptracer");
  const std::string xml = write_file(dir, "scene.xml", R"(<scene version="0.6.0">
  <integrator type="ptracer"><integer name="maxDepth" value="6"/>
    <integer name="rrDepth" value="3"/><integer name="granularity" value="1000"/></integrator>
  <sensor type="perspective"><float name="fov" value="30"/>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
  <emitter type="constant"><spectrum name="radiance" value="0.5"/></emitter>
  <shape type="sphere"/>
</scene>)");
  const SceneDescription desc = load_scene_description(xml);
  EXPECT_EQ(desc.render.integrator, "ptracer");
  EXPECT_EQ(desc.render.said("--max-depth"), "6");
  EXPECT_EQ(desc.render.said("--rr-depth"), "3");
  EXPECT_NE(make_integrator(desc.render.integrator), nullptr);
}

// Mitsuba's ptracer reads no hideEmitters and draws the lights seen directly, so the flag is
// noted and dropped; bruteForce, an image emlt does not render, is a divergence (said before
// the render, refused by --strict), but only when switched on.
TEST(Loader, XmlParticleTracerHideEmittersAndBruteForce) {
  const auto dir = test::scratch_dir("ptracer-flags");
  const auto scene = [&](const std::string& name, const std::string& flags) {
    return load_scene_description(write_file(dir, name, R"(<scene version="0.6.0">
  <integrator type="ptracer">)" + flags + R"(</integrator>
  <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/>
    <integer name="height" value="8"/></film></sensor>
  <shape type="sphere"><emitter type="area"><spectrum name="radiance" value="1"/></emitter></shape>
</scene>)"));
  };
  const SceneDescription hidden = scene("hide.xml", R"(<boolean name="hideEmitters" value="true"/>
    <boolean name="bruteForce" value="false"/>)");
  EXPECT_FALSE(hidden.render.said("--hide-emitters"));
  EXPECT_TRUE(
      any_contains(hidden.warnings, "'hideEmitters' is not a parameter of Mitsuba's ptracer"));
  EXPECT_TRUE(hidden.divergences.empty()) << hidden.divergences.front().message;
  const SceneDescription brute = scene("brute.xml", R"(<boolean name="bruteForce" value="true"/>)");
  ASSERT_EQ(brute.divergences.size(), 1u);
  EXPECT_NE(brute.divergences.front().message.find("'bruteForce' is not supported"),
            std::string::npos);
  // The path tracer still reads the flag.
  EXPECT_TRUE(load_scene_description(write_file(dir, "path.xml", R"(<scene version="0.6.0">
  <integrator type="path"><boolean name="hideEmitters" value="true"/></integrator>
  <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/>
    <integer name="height" value="8"/></film></sensor>
  <shape type="sphere"/>
</scene>)"))
                  .render.said("--hide-emitters") == "true");
}

// The path and direct integrators read strictNormals (default false), and emlt renders
// either: the scene stays exact and the description says which.
TEST(Loader, MitsubaStrictNormalsIsReadByThePathAndDirectIntegrators) {
  const auto dir = test::scratch_dir("strict-normals");
  const auto with = [&](const std::string& name, const std::string& integrator) {
    std::string xml = small_xml("");
    xml.replace(xml.find("<sensor"), 0, integrator + "\n");
    return load_scene_description(write_file(dir, name, xml));
  };
  const SceneDescription none = with("none.xml", "");
  EXPECT_FALSE(none.strict_normals);  // Mitsuba's default integrator is its path tracer
  const SceneDescription path = with("path.xml", "<integrator type=\"path\"/>");
  EXPECT_FALSE(path.strict_normals);
  const SceneDescription strict = with(
      "strict.xml",
      "<integrator type=\"direct\"><boolean name=\"strictNormals\" value=\"true\"/></integrator>");
  EXPECT_TRUE(strict.strict_normals);
  EXPECT_EQ(strict.verdict(), "exact");
  EXPECT_TRUE(with("bdpt.xml", "<integrator type=\"bdpt\"/>").strict_normals);
  EXPECT_TRUE(with("ptracer.xml", "<integrator type=\"ptracer\"/>").strict_normals);
}

// A scene description holds what the file says about rendering and nothing more: a file
// that names no integrator and no sample count leaves them to the engine and the command line.
TEST(Loader, TheDescriptionCarriesOnlyWhatTheFileSaysAboutRendering) {
  const auto dir = test::scratch_dir("render-request");
  const SceneDescription silent =
      load_scene_description(write_file(dir, "silent.xml", small_xml("")));
  EXPECT_TRUE(silent.render.integrator.empty());
  EXPECT_TRUE(silent.render.options.empty());
  const RenderSettings engine;
  const RenderSettings s = settings_for(silent.render);
  EXPECT_EQ(s.integrator, engine.integrator);
  EXPECT_EQ(s.spp, engine.spp);
  EXPECT_EQ(s.max_depth, engine.max_depth);
  const SceneDescription said = load_scene_description(write_file(dir, "said.xml", small_xml(R"(
  <integrator type="bdpt"><integer name="maxDepth" value="4"/></integrator>)")));
  EXPECT_EQ(said.render.integrator, "bdpt");
  EXPECT_EQ(said.render.said("--max-depth"), "4");
  EXPECT_FALSE(said.render.said("--rr-depth"));  // not said: the engine's
  EXPECT_EQ(settings_for(said.render).rr_depth, engine.rr_depth);
  EXPECT_EQ(settings_for(said.render).max_depth, 4);
}
