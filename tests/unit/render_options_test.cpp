// The render options as the integrators and the run loop declare them (render_option.h):
// each flag once, refusals in the option's own words, every value that changes a render
// recorded in the checkpoint's identity, and the options a scene file may set meaning there
// what the flag means on the command line.
#include <gtest/gtest.h>

#include <set>

#include "emlt/core/error.h"
#include "emlt/integrators/registry.h"
#include "emlt/run/scene_settings.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/settings/render_option.h"
#include "emlt/settings/scene_options.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

// Two different values the option takes (its range's ends, or its first two words).
std::pair<std::string, std::string> two_values(const RenderOption& option) {
  const OptionValues& v = option.values;
  switch (v.kind) {
    case OptionValues::Kind::Whole: {
      const auto low = int64_t(v.low), high = v.high >= 9.2e18 ? INT64_MAX : int64_t(v.high);
      return {std::to_string(low), std::to_string(high)};
    }
    case OptionValues::Kind::Real: {
      const double low = v.low_open ? v.low + (std::min(v.high, 1.0) - v.low) / 2 : v.low;
      return {recorded_number(low), recorded_number(std::min(v.high, 1e6))};
    }
    case OptionValues::Kind::Word:
      return {v.words.at(0), v.words.at(1)};
    case OptionValues::Kind::Text:
      break;
  }
  return {"", "other"};  // a file option records whether it is given, not where it points
}

}  // namespace

TEST(RenderOptions, EachFlagIsDeclaredOnceWithHelpAndAWayToSetIt) {
  std::set<std::string> flags;
  for (const RenderOption& option : render_options()) {
    EXPECT_TRUE(flags.insert(option.flag).second) << option.flag;
    EXPECT_EQ(option.flag.rfind("--", 0), 0u) << option.flag;
    EXPECT_FALSE(option.help.empty()) << option.flag;
    EXPECT_TRUE(bool(option.assign)) << option.flag;
  }
  // The integrators' own knobs are among them, not only the run loop's.
  for (const char* flag : {"--spp", "--max-depth", "--bdpt-strategies", "--mpp", "--gamlt-cone",
                           "--ensemble-alpha", "--pss-sigma"})
    EXPECT_TRUE(flags.count(flag)) << flag;
}

TEST(RenderOptions, ValuesOutsideTheRangeAreRefusedInTheOptionsOwnWords) {
  RenderSettings s;
  const auto find = [](const std::string& flag) -> const RenderOption& {
    for (const RenderOption& o : render_options())
      if (o.flag == flag) return o;
    throw Error("no option " + flag);
  };
  EXPECT_EQ(test::error_of([&] { find("--spp").set(s, "0"); }),
            "--spp must be a whole number from 1 to 2^24 (about 16.8 million) (got 0)");
  EXPECT_EQ(test::error_of([&] { find("--pss-sigma").set(s, "0"); }),
            "--pss-sigma must be a number above 0, at most 0.5 (got 0)");
  EXPECT_EQ(test::error_of([&] { find("--ensemble-guides").set(s, "random"); }),
            "--ensemble-guides must be counter or nearby (got random)");
  EXPECT_NE(test::error_of([&] { find("--seed").set(s, "9223372036854775808"); }), "");
  find("--ensemble-guides").set(s, "nearby");
  EXPECT_TRUE(s.ensemble_nearby_guides);
  find("--bootstrap").set(s, "5000");
  EXPECT_EQ(s.bootstrap_samples, 5000);
  EXPECT_FALSE(s.bootstrap_grows);  // a pool of the size given is kept
  find("--seed").set(s, "9223372036854775807");
  EXPECT_EQ(s.seed, 9223372036854775807ull);
}

// A checkpoint resumed with another value of an option that changes the render must be
// refused: every recorded option's record tells its values apart.
TEST(RenderOptions, EveryRecordedOptionTellsItsValuesApart) {
  int recorded = 0;
  for (const RenderOption& option : render_options()) {
    if (!option.recorded) continue;
    ++recorded;
    const auto [a, b] = two_values(option);
    RenderSettings sa, sb;
    sa.integrator = sb.integrator = "mlt";
    option.set(sa, a);
    option.set(sb, b);
    EXPECT_NE(option.recorded(sa), option.recorded(sb)) << option.flag << " " << a << " / " << b;
  }
  EXPECT_GE(recorded, 25);
  // The budget and the threads are not part of a render's identity: a resume may grow the
  // budget, and the image is the same at any thread count.
  for (const RenderOption& option : render_options()) {
    if (option.flag == "--spp" || option.flag == "--mpp" || option.flag == "--time" ||
        option.flag == "--threads") {
      EXPECT_FALSE(bool(option.recorded)) << option.flag;
    }
  }
}

// A checkpoint records only the options the render's integrator reads: the path-space
// strategies' options (gamlt cones, the ensemble) for mlt, gamlt and emlt, the primary-sample
// ones for pssmlt and mmlt, the shared ones for all. A pt checkpoint thus survives a change
// of the gamlt cones' default.
TEST(RenderOptions, OnlyTheOptionsAnIntegratorReadsApplyToIt) {
  const auto applies = [](const std::string& flag, const std::string& integrator) {
    RenderSettings s;
    s.integrator = integrator;
    for (const RenderOption& o : render_options())
      if (o.flag == flag) return !o.applies || o.applies(s);
    throw Error("no option " + flag);
  };
  for (const char* integrator : {"mlt", "gamlt", "memlt", "emlt"}) {
    EXPECT_TRUE(applies("--manifold-lambda", integrator)) << integrator;
    EXPECT_TRUE(applies("--gamlt-cone", integrator)) << integrator;
    EXPECT_TRUE(applies("--ensemble-alpha", integrator)) << integrator;
    EXPECT_FALSE(applies("--pss-sigma", integrator)) << integrator;
  }
  for (const char* integrator : {"pt", "bdpt", "direct", "ptracer", "pssmlt", "mmlt"}) {
    EXPECT_FALSE(applies("--manifold-lambda", integrator)) << integrator;
    EXPECT_FALSE(applies("--gamlt-cone", integrator)) << integrator;
    EXPECT_FALSE(applies("--ensemble-size", integrator)) << integrator;
  }
  EXPECT_TRUE(applies("--pss-sigma", "pssmlt"));
  EXPECT_TRUE(applies("--large-step", "mmlt"));
  for (const char* integrator : {"pt", "mlt", "pssmlt"}) {
    EXPECT_TRUE(applies("--max-depth", integrator)) << integrator;
    EXPECT_TRUE(applies("--seed", integrator)) << integrator;
    EXPECT_TRUE(applies("--chains", integrator)) << integrator;  // the pss chains too
  }
}

// The options a scene file may set are read by the loaders through their declarations
// (scene_options.h): a Mitsuba parameter and a JSON key mean what the flag means, take the
// flag's values and are refused in its words; each is also on the command line.
TEST(RenderOptions, SceneFileOptionsMeanInAFileWhatTheirFlagsMean) {
  const auto dir = test::scratch_dir("render-options-scene-file");
  const auto on_command_line = [](const std::string& flag) {
    for (const RenderOption& o : render_options())
      if (o.flag == flag) return true;
    return false;
  };
  std::set<std::string> mitsuba_names;
  for (const SceneFileOption& o : scene_file_options()) {
    EXPECT_TRUE(on_command_line(o.option.flag)) << o.option.flag;
    mitsuba_names.insert(o.mitsuba);
    const bool sampler = o.element == MitsubaElement::Sampler;
    const std::string value =
        o.boolean() ? o.word(true) : std::to_string(int64_t(o.option.values.low) + 3);
    const std::string out_of_range =
        o.boolean() ? "maybe" : std::to_string(int64_t(o.option.values.low) - 1);
    const auto xml = [&](const std::string& text) {
      const std::string parameter = std::string("<") + (o.boolean() ? "boolean" : "integer") +
                                    " name=\"" + o.mitsuba + "\" value=\"" + text + "\"/>";
      return test::write_file(
          dir, o.mitsuba + ".xml",
          "<scene version=\"0.6.0\"><integrator type=\"path\">" +
              (sampler ? std::string() : parameter) +
              "</integrator><sensor type=\"perspective\"><sampler type=\"independent\">" +
              (sampler ? parameter : std::string()) +
              "</sampler><film type=\"hdrfilm\"><integer name=\"width\" value=\"4\"/>"
              "<integer name=\"height\" value=\"4\"/></film></sensor>"
              "<emitter type=\"constant\"/></scene>");
    };
    const auto json = [&](const std::string& text) {
      return test::write_file(
          dir, o.json_key() + ".json",
          R"({"camera": {"lookat": {"origin": [0,0,-5], "target": [0,0,0], "up": [0,1,0]},
                          "fov": 40, "width": 4, "height": 4},
              "shapes": [{"type": "rectangle", "emission": [1,1,1]}],
              "integrator": {")" +
              o.json_key() + "\": " + text + "}}");
    };
    RenderSettings by_flag;
    o.option.set(by_flag, value);
    for (const std::string& file : {xml(value), json(value)}) {
      const SceneDescription desc = load_scene_description(file);
      EXPECT_TRUE(desc.warnings.empty()) << file << ": " << desc.warnings.front();
      EXPECT_EQ(desc.render.said(o.option.flag), value) << file;
      const RenderSettings by_file = settings_for(desc.render);
      for (const RenderOption& any : render_options()) {
        if (!any.recorded) continue;
        EXPECT_EQ(any.recorded(by_file), any.recorded(by_flag)) << any.flag << " in " << file;
      }
      EXPECT_EQ(by_file.spp, by_flag.spp) << file;
    }
    if (o.boolean()) continue;  // a boolean's refusal is the file format's ("expected true...")
    for (const std::string& file : {xml(out_of_range), json(out_of_range)}) {
      const std::string message = test::error_of([&] { load_scene_description(file); });
      EXPECT_NE(message.find("must be " + o.option.values.takes + " (got " + out_of_range + ")"),
                std::string::npos)
          << message;
    }
  }
  EXPECT_EQ(mitsuba_names,
            (std::set<std::string>{"sampleCount", "maxDepth", "rrDepth", "hideEmitters"}));
}
