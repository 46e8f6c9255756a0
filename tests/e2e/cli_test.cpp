// The `emlt` command as a user runs it: outputs, summaries, and every bad input giving
// one clear line, a non-zero exit and no output file.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "emlt/image/image.h"
#include "emlt/image/image_metrics.h"
#include "support/cli_checks.h"
#include "support/test_support.h"

using namespace emlt;
namespace fs = std::filesystem;
using test::cornell;
using test::count_lines;
using test::emlt_cmd;
using test::expect_clean_failure;

namespace {

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

}  // namespace

TEST(Cli, RendersCornellBoxWithPreviewAndSummary) {
  const fs::path dir = test::scratch_dir("render");
  const fs::path out = dir / "cornell.exr";
  std::string text;
  ASSERT_EQ(0, test::run_command(emlt_cmd("render " + cornell() + " -o " + out.string() +
                                          " --spp 4 --width 32 --height 32 --quiet"),
                                 &text))
      << text;
  EXPECT_TRUE(fs::exists(out));
  EXPECT_TRUE(fs::exists(dir / "cornell.png"));
  EXPECT_NE(text.find("samples/s"), std::string::npos) << text;
  const Image image = read_image(out.string());
  EXPECT_EQ(image.width, 32);
  double sum = 0.0;
  for (const Rgb& p : image.pixels) sum += luminance(p);
  EXPECT_GT(sum / image.pixels.size(), 0.05);
}

TEST(Cli, SameSeedGivesIdenticalImagesOnOneAndTwoThreads) {
  const fs::path dir = test::scratch_dir("threads");
  const std::string common = " --spp 4 --width 48 --height 48 --seed 7 --quiet";
  ASSERT_EQ(0, test::run_command(emlt_cmd("render " + cornell() + " -o " +
                                          (dir / "one.pfm").string() + common + " --threads 1")));
  ASSERT_EQ(0, test::run_command(emlt_cmd("render " + cornell() + " -o " +
                                          (dir / "two.pfm").string() + common + " --threads 2")));
  const Image a = read_image((dir / "one.pfm").string()),
              b = read_image((dir / "two.pfm").string());
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  EXPECT_EQ(0, std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Rgb)));
}

TEST(Cli, JsonAndMitsubaCornellBoxesRenderTheSameImage) {
  const fs::path dir = test::scratch_dir("formats");
  const std::string common = " --spp 64 --width 32 --height 32 --quiet --integrator pt";
  ASSERT_EQ(0, test::run_command(emlt_cmd("render " + cornell("scene.json") + " -o " +
                                          (dir / "json.pfm").string() + common)));
  ASSERT_EQ(0, test::run_command(emlt_cmd("render " + cornell("scene.xml") + " -o " +
                                          (dir / "xml.pfm").string() + common + " --seed 2")));
  const Image a = read_image((dir / "json.pfm").string()),
              b = read_image((dir / "xml.pfm").string());
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  // Independent seeds: equal up to noise, per channel and per image region.
  for (int c = 0; c < 3; ++c) {
    double ma = 0.0, mb = 0.0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
      ma += a.pixels[i][c];
      mb += b.pixels[i][c];
    }
    EXPECT_NEAR(ma, mb, 0.02 * ma) << "channel " << c;
  }
  // Left and right halves: a mirrored image would swap the red and green walls.
  double red_left_a = 0.0, red_left_b = 0.0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 8; ++x) {
      red_left_a += a.at(x, y).x - a.at(x, y).y;
      red_left_b += b.at(x, y).x - b.at(x, y).y;
    }
  EXPECT_GT(red_left_a, 0.0);
  EXPECT_GT(red_left_b, 0.0);
}

// What a scene file says about rendering, the command line overrides: a Mitsuba scene that
// hides its lights shows them with --hide-emitters false, and one that shows them hides them
// with --hide-emitters true (the camera sees nothing but a light, so hidden is black).
TEST(Cli, TheCommandLineOverridesWhatTheSceneFileSets) {
  const fs::path dir = test::scratch_dir("cli-overrides");
  const auto scene = [&](const std::string& name, const std::string& hide) {
    const fs::path path = dir / name;
    write_file(path, R"(<scene version="0.6.0">
  <integrator type="path"><boolean name="hideEmitters" value=")" +
                         hide + R"("/></integrator>
  <sensor type="perspective"><transform name="toWorld"><lookat origin="0,0,4" target="0,0,0" up="0,1,0"/></transform>
    <sampler type="independent"><integer name="sampleCount" value="2"/></sampler>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
  <shape type="rectangle"><transform name="toWorld"><scale value="4"/></transform>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>)");
    return path.string();
  };
  const auto brightness = [&](const std::string& file, const std::string& flags) {
    const fs::path out = dir / "o.exr";
    std::string text;
    EXPECT_EQ(0, test::run_command(emlt_cmd("render " + file + " -o " + out.string() + " " + flags),
                                   &text))
        << text;
    const Image image = read_image(out.string());
    double sum = 0;
    for (const Rgb& p : image.pixels) sum += p.x + p.y + p.z;
    return sum / double(image.pixels.size());
  };
  const std::string hidden = scene("hidden.xml", "true"), shown = scene("shown.xml", "false");
  EXPECT_EQ(brightness(hidden, ""), 0.0);
  EXPECT_GT(brightness(hidden, "--hide-emitters false"), 2.9);  // 3 channels of radiance 1
  EXPECT_GT(brightness(shown, ""), 2.9);
  EXPECT_EQ(brightness(shown, "--hide-emitters true"), 0.0);
  EXPECT_EQ(brightness(shown, "--hide-emitters true --integrator bdpt"), 0.0);
  // `emlt info` says what the file sets.
  std::string info;
  ASSERT_EQ(0, test::run_command(emlt_cmd("info " + hidden), &info)) << info;
  EXPECT_NE(info.find("emitters hidden"), std::string::npos) << info;
  ASSERT_EQ(0, test::run_command(emlt_cmd("info " + shown), &info)) << info;
  EXPECT_EQ(info.find("emitters hidden"), std::string::npos) << info;
}

// The MIS split's own flags set nothing unless the split is on: said, not silently dropped.
TEST(Cli, MisSplitFlagsWithoutTheSplitAreSaidToBeIgnored) {
  const fs::path dir = test::scratch_dir("mis-alpha-ignored");
  const auto render = [&](const std::string& mis, const std::string& name) {
    std::string text;
    EXPECT_EQ(test::run_command(emlt_cmd("render " + cornell() +
                                         " --integrator direct --spp 1 --width 8 --height 8 " +
                                         mis + " --mis-alpha 0.3 --quiet -o " +
                                         (dir / name).string()),
                                &text),
              0)
        << text;
    return text;
  };
  const std::string ignored = render("--mis balance", "o.exr");
  EXPECT_NE(ignored.find("--mis-alpha is ignored without --mis second-order"), std::string::npos)
      << ignored;
  const std::string used = render("--mis second-order", "p.exr");
  EXPECT_EQ(used.find("is ignored"), std::string::npos) << used;
}

TEST(Cli, InfoDescribesTheScene) {
  std::string text;
  ASSERT_EQ(0, test::run_command(emlt_cmd("info " + cornell()), &text)) << text;
  EXPECT_NE(text.find("triangles"), std::string::npos);
  EXPECT_NE(text.find("area lights"), std::string::npos);
}

TEST(Cli, InfoGivesAFidelityVerdictAndStrictRefusesDivergences) {
  const fs::path dir = test::scratch_dir("verdict");
  const auto scene_with = [](const std::string& film_extra, const std::string& body) {
    return R"(<scene version="0.6.0">
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>)" +
           film_extra + R"(</film>
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
)" + body + "</scene>\n";
  };
  // High-quality edges under a Gaussian filter and an anisotropic rough plastic (rendered
  // with the mean roughness) are approximated; an emitter type Mitsuba does not have is not
  // supported at all.
  write_file(
      dir / "approx.xml",
      scene_with(
          R"(<boolean name="highQualityEdges" value="true"/>)",
          R"(<shape type="sphere"><bsdf type="roughplastic"><float name="alphaU" value="0.1"/><float name="alphaV" value="0.3"/></bsdf></shape>
  <emitter type="laser"/>
)"));
  write_file(dir / "exact.xml", scene_with(R"(<rfilter type="box"/>)", ""));
  std::string text;
  ASSERT_EQ(0, test::run_command(emlt_cmd("info " + (dir / "approx.xml").string()), &text)) << text;
  EXPECT_NE(text.find("verdict      approximated: 2 items, unsupported: 1 item\n"),
            std::string::npos)
      << text;
  ASSERT_EQ(0, test::run_command(emlt_cmd("info " + (dir / "exact.xml").string()), &text)) << text;
  EXPECT_NE(text.find("verdict      exact\n"), std::string::npos) << text;
  ASSERT_EQ(0, test::run_command(emlt_cmd("info --strict " + cornell("scene.xml")), &text)) << text;

  // A render says so before it starts, and --strict refuses, naming the file and line.
  const fs::path out = dir / "o.pfm";
  ASSERT_EQ(0, test::run_command(emlt_cmd("render " + (dir / "approx.xml").string() + " -o " +
                                          out.string() + " --spp 1 --quiet"),
                                 &text))
      << text;
  EXPECT_NE(text.find("not rendered exactly as its format means: approximated: 2 items, "
                      "unsupported: 1 item"),
            std::string::npos)
      << text;
  fs::remove(out);
  expect_clean_failure("render --strict " + (dir / "approx.xml").string() + " -o " + out.string(),
                       "approx.xml: line 4: 'highQualityEdges' is not supported", out);
  expect_clean_failure("info --strict " + (dir / "approx.xml").string(),
                       "refused by --strict; 2 more", out);
}

// `emlt info --json` gives each warning its kind, as the verdict counts them; a note (here
// a sampler's seed, which steers only sampling) is a warning but no item.
TEST(Cli, InfoJsonGivesEachWarningItsKind) {
  const fs::path dir = test::scratch_dir("info-json");
  write_file(dir / "scene.xml", R"(<scene version="0.6.0">
  <sensor type="perspective"><float name="fov" value="40"/>
    <sampler type="independent"><integer name="seed" value="3"/></sampler>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
      <boolean name="highQualityEdges" value="true"/></film>
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
  <emitter type="laser"/>
</scene>
)");
  std::string text;
  ASSERT_EQ(0, test::run_command(emlt_cmd("info --json " + (dir / "scene.xml").string()), &text))
      << text;
  const nlohmann::json j = nlohmann::json::parse(text);
  EXPECT_EQ(j["verdict"], "approximated: 1 item, unsupported: 1 item") << text;
  std::map<std::string, int> kinds;
  for (const auto& w : j["warnings"]) ++kinds[w["kind"].get<std::string>()];
  EXPECT_EQ(kinds["approximated"], 1) << text;
  EXPECT_EQ(kinds["unsupported"], 1) << text;
  EXPECT_EQ(kinds["note"], 1) << text;
  for (const auto& w : j["warnings"]) {
    if (w["kind"] != "note") continue;
    EXPECT_NE(w["message"].get<std::string>().find("'seed'"), std::string::npos) << text;
  }
}

TEST(CliBadInput, MissingSceneFile) {
  const fs::path dir = test::scratch_dir("missing");
  expect_clean_failure("render " + (dir / "nope.json").string() + " -o " + (dir / "o.exr").string(),
                       "nope.json", dir / "o.exr");
}

TEST(CliBadInput, MalformedJson) {
  const fs::path dir = test::scratch_dir("malformed");
  write_file(dir / "bad.json", "{ \"camera\": { \"fov\": 40, }");
  expect_clean_failure("render " + (dir / "bad.json").string() + " -o " + (dir / "o.exr").string(),
                       "bad.json", dir / "o.exr");
}

TEST(CliBadInput, MalformedXml) {
  const fs::path dir = test::scratch_dir("malformed-xml");
  write_file(dir / "bad.xml", "<scene version=\"0.6.0\"><shape type=\"obj\"></scene>");
  expect_clean_failure("render " + (dir / "bad.xml").string() + " -o " + (dir / "o.exr").string(),
                       "bad.xml", dir / "o.exr");
}

TEST(CliBadInput, SceneWithoutEmitter) {
  const fs::path dir = test::scratch_dir("dark");
  write_file(dir / "dark.json",
             R"({"camera": {"lookat": {"origin": [0,0,-3], "target": [0,0,0], "up": [0,1,0]},
    "fov": 40, "width": 16, "height": 16},
    "materials": {"white": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "white"}]})");
  expect_clean_failure("render " + (dir / "dark.json").string() + " -o " + (dir / "o.exr").string(),
                       "emitter", dir / "o.exr");
}

TEST(CliBadInput, ZeroAndAbsurdResolutions) {
  const fs::path dir = test::scratch_dir("resolution");
  expect_clean_failure("render " + cornell() + " -o " + (dir / "o.exr").string() + " --width 0",
                       "width", dir / "o.exr");
  expect_clean_failure(
      "render " + cornell() + " -o " + (dir / "o.exr").string() + " --width 100000 --height 100000",
      "width", dir / "o.exr");
}

TEST(CliBadInput, UnknownFlagAndIntegrator) {
  const fs::path dir = test::scratch_dir("flags");
  expect_clean_failure(
      "render " + cornell() + " -o " + (dir / "o.exr").string() + " --frobnicate 3", "frobnicate",
      dir / "o.exr");
  expect_clean_failure(
      "render " + cornell() + " -o " + (dir / "o.exr").string() + " --integrator magic", "magic",
      dir / "o.exr");
}

TEST(CliBadInput, UnwritableOrUnknownOutput) {
  const fs::path dir = test::scratch_dir("output");
  expect_clean_failure("render " + cornell() + " -o " + (dir / "o.jpeg").string(), "o.jpeg",
                       dir / "o.jpeg");
  expect_clean_failure("render " + cornell() + " -o " + (dir / "no-such-dir" / "o.exr").string(),
                       "no-such-dir", dir / "no-such-dir" / "o.exr");
}

TEST(CliBadInput, MissingMeshNamesTheMesh) {
  const fs::path dir = test::scratch_dir("mesh");
  write_file(dir / "s.json",
             R"({"camera": {"lookat": {"origin": [0,0,-3], "target": [0,0,0], "up": [0,1,0]},
    "fov": 40, "width": 16, "height": 16},
    "shapes": [{"type": "obj", "file": "ghost.obj", "emission": [1,1,1]}]})");
  expect_clean_failure("render " + (dir / "s.json").string() + " -o " + (dir / "o.exr").string(),
                       "ghost.obj", dir / "o.exr");
}

TEST(CliBadInput, NanTexelsInEnvironmentMap) {
  const fs::path dir = test::scratch_dir("nan");
  Image map(8, 4, Rgb(1.0f));
  map.at(3, 2) = Rgb(std::nanf(""));
  // PFM keeps the NaN bits exactly as written.
  write_image((dir / "sky.pfm").string(), map);
  write_file(dir / "s.json",
             R"({"camera": {"lookat": {"origin": [0,0,-3], "target": [0,0,0], "up": [0,1,0]},
    "fov": 40, "width": 16, "height": 16},
    "environment": {"type": "envmap", "file": "sky.pfm"},
    "shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1}]})");
  expect_clean_failure("render " + (dir / "s.json").string() + " -o " + (dir / "o.exr").string(),
                       "sky.pfm", dir / "o.exr");
}

TEST(CliCompare, JsonMetricsEqualTheLibraryOnTheSameFiles) {
  const fs::path dir = test::scratch_dir("compare");
  const std::string common = " --width 24 --height 24 --quiet";
  ASSERT_EQ(0, test::run_command(emlt_cmd("render " + cornell() + " -o " +
                                          (dir / "ref.pfm").string() + common + " --spp 64")));
  ASSERT_EQ(0,
            test::run_command(emlt_cmd("render " + cornell() + " -o " + (dir / "img.pfm").string() +
                                       common + " --spp 4 --seed 3")));
  std::string text;
  ASSERT_EQ(0, test::run_command(emlt_cmd("compare " + (dir / "ref.pfm").string() + " " +
                                          (dir / "img.pfm").string() + " --json --scene " +
                                          cornell() + " --error-map " + (dir / "err.png").string()),
                                 &text))
      << text;
  const auto j = nlohmann::json::parse(text);
  const Image ref = read_image((dir / "ref.pfm").string()),
              img = read_image((dir / "img.pfm").string());
  const ImageMetrics m = compare_images(ref, img);
  EXPECT_NEAR(j["mse"].get<double>(), m.mse, 1e-9 + 1e-6 * m.mse);
  EXPECT_NEAR(j["relmse"].get<double>(), m.rel_mse, 1e-9 + 1e-6 * m.rel_mse);
  EXPECT_NEAR(j["mean_ratio"].get<double>(), m.mean_ratio, 1e-6);
  // The light is visible in the Cornell box, so excluding it lowers the MSE.
  EXPECT_LT(j["mse_no_emitter"].get<double>(), m.mse);
  EXPECT_GT(m.mse, 0.0);
  EXPECT_TRUE(fs::exists(dir / "err.png"));
}

TEST(CliCompare, MismatchedSizesNameTheFile) {
  const fs::path dir = test::scratch_dir("compare-bad");
  write_image((dir / "a.pfm").string(), Image(4, 4, Rgb(1.0f)));
  write_image((dir / "b.pfm").string(), Image(5, 4, Rgb(1.0f)));
  std::string text;
  EXPECT_NE(0, test::run_command(
                   emlt_cmd("compare " + (dir / "a.pfm").string() + " " + (dir / "b.pfm").string()),
                   &text));
  EXPECT_NE(text.find("b.pfm"), std::string::npos) << text;
  EXPECT_NE(text.find("sizes differ"), std::string::npos) << text;
}

TEST(Cli, BdptWritesOneImagePerStrategyThatSumToTheRender) {
  const fs::path dir = test::scratch_dir("bdpt");
  const fs::path strategies = dir / "strategies";
  fs::create_directories(strategies);
  std::string text;
  ASSERT_EQ(0,
            test::run_command(
                emlt_cmd("render " + cornell() + " -o " + (dir / "bdpt.pfm").string() +
                         " --integrator bdpt --spp 4 --width 16 --height 16 --max-depth 3 --quiet"
                         " --bdpt-strategies " +
                         strategies.string()),
                &text))
      << text;
  const Image image = read_image((dir / "bdpt.pfm").string());
  // Paths of at most 3 segments: strategies (s, t) with s + t - 1 <= 3 and t >= 1.
  Image sum(image.width, image.height);
  int files = 0;
  for (const auto& entry : fs::directory_iterator(strategies)) {
    const Image part = read_image(entry.path().string());
    for (size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += part.pixels[i];
    ++files;
  }
  EXPECT_GE(files, 9);
  double total = 0.0, difference = 0.0;
  for (size_t i = 0; i < sum.pixels.size(); ++i) {
    total += luminance(image.pixels[i]);
    difference += std::abs(luminance(image.pixels[i]) - luminance(sum.pixels[i]));
  }
  EXPECT_GT(total, 0.0);
  EXPECT_LT(difference, 1e-3 * total);
}

TEST(Cli, MltWritesStatisticsAndRejectsUnknownStrategies) {
  const fs::path dir = test::scratch_dir("mlt");
  std::string text;
  ASSERT_EQ(0,
            test::run_command(emlt_cmd("render " + cornell() + " -o " + (dir / "mlt.pfm").string() +
                                       " --integrator mlt --mutations bidir=1 --mpp 4 --bootstrap "
                                       "5000 --width 16 --height 16 --quiet"
                                       " --stats " +
                                       (dir / "stats.json").string()),
                              &text))
      << text;
  EXPECT_TRUE(fs::exists(dir / "mlt.pfm"));
  std::ifstream in(dir / "stats.json");
  const auto stats = nlohmann::json::parse(in);
  EXPECT_GT(stats["b"].get<double>(), 0.0);
  EXPECT_EQ(stats["mutations"].get<uint64_t>(), 4u * 16u * 16u);
  EXPECT_EQ(stats["strategies"][0]["name"], "bidir");
  EXPECT_EQ(stats["strategies"][0]["proposed"].get<uint64_t>(), 4u * 16u * 16u);
  EXPECT_NE(text.find("mean a"), std::string::npos) << text;
  expect_clean_failure("render " + cornell() + " -o " + (dir / "o.exr").string() +
                           " --integrator mlt --mutations teleport=1",
                       "teleport", dir / "o.exr");
}

// erpt's --stats: b with its error from the luminance samples, the chains its seeds started
// and their steps, each strategy's proposals (which add up to the steps).
TEST(Cli, ErptWritesItsChainStatistics) {
  const fs::path dir = test::scratch_dir("erpt_stats");
  std::string text;
  ASSERT_EQ(0, test::run_command(
                   emlt_cmd("render " + cornell() + " -o " + (dir / "erpt.pfm").string() +
                            " --integrator erpt --spp 2 --erpt-chain-length 8 --bootstrap 4000"
                            " --width 16 --height 16 --quiet --stats " +
                            (dir / "stats.json").string()),
                   &text))
      << text;
  std::ifstream in(dir / "stats.json");
  const auto stats = nlohmann::json::parse(in);
  EXPECT_GT(stats["b"].get<double>(), 0.0);
  EXPECT_GT(stats["b_standard_error"].get<double>(), 0.0);
  EXPECT_EQ(stats["bootstrap_samples"].get<uint64_t>(), 4000u);
  const uint64_t chains = stats["chains"].get<uint64_t>();
  EXPECT_GT(chains, 0u);
  EXPECT_EQ(stats["mutations"].get<uint64_t>(), 8u * chains);
  ASSERT_EQ(stats["strategies"].size(), 3u);
  EXPECT_EQ(stats["strategies"][0]["name"], "lens");
  uint64_t proposed = 0;
  for (const auto& s : stats["strategies"]) proposed += s["proposed"].get<uint64_t>();
  EXPECT_EQ(proposed, 8u * chains);
  EXPECT_NE(text.find("erpt: b = "), std::string::npos) << text;
}

// --bootstrap-seed fixes the bootstrap (b and the start paths) while --seed varies the
// chains: the same b and different images for two seeds; equal to --seed, the default.
TEST(Cli, BootstrapSeedKeepsThePoolWhileTheSeedVariesTheChains) {
  const fs::path dir = test::scratch_dir("bootstrap_seed");
  const auto run = [&](const std::string& name, const std::string& flags) {
    std::string text;
    EXPECT_EQ(0, test::run_command(
                     emlt_cmd("render " + cornell() + " -o " + (dir / (name + ".pfm")).string() +
                              " --integrator mlt --mpp 2 --bootstrap 4000 --width 16 --height 16 -q"
                              " --stats " +
                              (dir / (name + ".json")).string() + " " + flags),
                     &text))
        << text;
    std::ifstream in(dir / (name + ".json"));
    return std::make_pair(nlohmann::json::parse(in)["b"].get<double>(),
                          read_image((dir / (name + ".pfm")).string()));
  };
  const auto same_bits = [](const Image& a, const Image& b) {
    return a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Rgb)) == 0;
  };
  const auto [b1, seed1] = run("seed1", "--seed 1");
  const auto [b2, seed2] = run("seed2", "--seed 2");
  const auto [b2_pool1, seed2_pool1] = run("seed2_pool1", "--seed 2 --bootstrap-seed 1");
  const auto [b2_pool2, seed2_pool2] = run("seed2_pool2", "--seed 2 --bootstrap-seed 2");
  EXPECT_NE(b1, b2);                            // each seed its own pool by default
  EXPECT_EQ(b2_pool1, b1);                      // the pool of seed 1 ...
  EXPECT_FALSE(same_bits(seed2_pool1, seed1));  // ... under other chains
  EXPECT_FALSE(same_bits(seed2_pool1, seed2));
  EXPECT_TRUE(same_bits(seed2_pool2, seed2));
  EXPECT_EQ(b2_pool2, b2);
}

// pssmlt (over BDPT and over the path tracer) and mmlt: statistics per step kind and per
// path length.
TEST(Cli, PrimarySampleSpaceIntegratorsWriteStatistics) {
  const fs::path dir = test::scratch_dir("pss");
  for (const auto& [integrator, tracer] : {std::pair<std::string, std::string>{"pssmlt", "bdpt"},
                                           {"pssmlt", "pt"},
                                           {"mmlt", "bdpt"}}) {
    SCOPED_TRACE(integrator + " " + tracer);
    std::string text;
    const fs::path stats_path = dir / (integrator + "-" + tracer + ".json");
    ASSERT_EQ(0,
              test::run_command(
                  emlt_cmd("render " + cornell() + " -o " + (dir / (integrator + ".pfm")).string() +
                           " --integrator " + integrator + " --pss-tracer " + tracer +
                           " --large-step 0.5"
                           " --mpp 4 --chains 64 --bootstrap 5000 --width 16 --height 16 --quiet"
                           " --stats " +
                           stats_path.string()),
                  &text))
        << text;
    std::ifstream in(stats_path);
    const auto stats = nlohmann::json::parse(in);
    EXPECT_GT(stats["b"].get<double>(), 0.0);
    EXPECT_EQ(stats["mutations"].get<uint64_t>(), 4u * 16u * 16u);  // 1024 = 64 chains x 16
    EXPECT_EQ(stats["strategies"][0]["name"], "large");
    EXPECT_EQ(stats["strategies"][1]["name"], "small");
    EXPECT_EQ(stats["strategies"][0]["proposed"].get<uint64_t>() +
                  stats["strategies"][1]["proposed"].get<uint64_t>(),
              4u * 16u * 16u);
    // Then one row per path length (MMLT: the chain's; PSSMLT: the proposal's longest
    // contributing path, and "no light"): every proposal and acceptance counted once.
    EXPECT_EQ(stats["strategies"][2]["name"], "length 3");
    uint64_t proposed = 0, accepted = 0, by_length_proposed = 0, by_length_accepted = 0;
    for (size_t i = 0; i < stats["strategies"].size(); ++i) {
      const auto& row = stats["strategies"][i];
      const std::string name = row["name"].get<std::string>();
      uint64_t& p = i < 2 ? proposed : by_length_proposed;
      uint64_t& a = i < 2 ? accepted : by_length_accepted;
      p += row["proposed"].get<uint64_t>();
      a += row["accepted"].get<uint64_t>();
      if (i >= 2) {
        EXPECT_TRUE(name.starts_with("length ") || name == "no light") << name;
      }
    }
    EXPECT_EQ(by_length_proposed, proposed);
    EXPECT_EQ(by_length_accepted, accepted);
    EXPECT_GT(accepted, 0u);
    const auto& last = stats["strategies"][stats["strategies"].size() - 1];
    EXPECT_EQ(last["name"] == "no light", integrator == "pssmlt") << last;
    // Light arrives on paths of several lengths (the Cornell box's indirect light).
    int lit_lengths = 0;
    for (size_t i = 2; i < stats["strategies"].size(); ++i)
      lit_lengths += stats["strategies"][i]["name"] != "no light" &&
                     stats["strategies"][i]["accepted"].get<uint64_t>() > 0;
    EXPECT_GE(lit_lengths, 3);
  }
}

TEST(Cli, EmltWritesEnsembleStatisticsAndTheAnisotropyMap) {
  const fs::path dir = test::scratch_dir("emlt");
  std::string text;
  ASSERT_EQ(
      0, test::run_command(
             emlt_cmd("render " + cornell() + " -o " + (dir / "emlt.pfm").string() +
                      " --integrator emlt --mutations emlt-ani --mpp 8 --bootstrap 5000"
                      " --width 16 --height 16 --ensemble-size 32 --ensemble-neighbours 12 --quiet"
                      " --aniso-map " +
                      (dir / "aniso.png").string() + " --stats " + (dir / "stats.json").string()),
             &text))
      << text;
  EXPECT_TRUE(fs::exists(dir / "emlt.pfm"));
  EXPECT_TRUE(fs::exists(dir / "aniso.png"));
  std::ifstream in(dir / "stats.json");
  const auto stats = nlohmann::json::parse(in);
  EXPECT_EQ(stats["mutations"].get<uint64_t>(), 8u * 16u * 16u);
  EXPECT_EQ(stats["ensemble"]["size"].get<uint64_t>(), 32u);
  EXPECT_EQ(stats["ensemble"]["neighbours"].get<uint64_t>(), 12u);
  EXPECT_EQ(stats["ensemble"]["iterations"].get<uint64_t>(), 4u);  // 256 pixels / 64 paths
  EXPECT_EQ(stats["strategies"][1]["name"], "emlt-aniso");
  EXPECT_NE(text.find("swaps"), std::string::npos) << text;
  EXPECT_GT(stats["chain_mutations_per_second"].get<double>(), 0.0);
  EXPECT_EQ(stats["direct_spp"].get<int>(), 8);  // one per mutation per pixel
  // The similarity's length scale changes which guides are chosen, hence the image.
  const std::string lin = "render " + cornell() +
                          " --integrator emlt --mutations emlt-lin --mpp 8 --bootstrap 5000"
                          " --width 16 --height 16 --ensemble-size 32 --quiet -o ";
  ASSERT_EQ(0, test::run_command(emlt_cmd(lin + (dir / "default.pfm").string())));
  ASSERT_EQ(0, test::run_command(emlt_cmd(lin + (dir / "scaled.pfm").string() +
                                          " --ensemble-similarity-length 50")));
  const auto bytes = [](const fs::path& path) {
    std::ifstream file(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(file), {});
  };
  // α's distribution over the linear kernels' stretches: ordered quartiles within the
  // paper's bounds (α_s = 0.05, α_l = 0.5).
  ASSERT_EQ(0, test::run_command(emlt_cmd(lin + (dir / "alpha.pfm").string() + " --stats " +
                                          (dir / "alpha.json").string())));
  std::ifstream alpha_in(dir / "alpha.json");
  const auto alpha = nlohmann::json::parse(alpha_in)["ensemble"]["alpha"];
  ASSERT_TRUE(alpha.is_object());
  EXPECT_GT(alpha["steps"].get<uint64_t>(), 0u);
  EXPECT_GE(alpha["min"].get<double>(), 0.05 - 1e-12);
  EXPECT_LE(alpha["min"].get<double>(), alpha["q1"].get<double>());
  EXPECT_LE(alpha["q1"].get<double>(), alpha["median"].get<double>());
  EXPECT_LE(alpha["median"].get<double>(), alpha["q3"].get<double>());
  EXPECT_LE(alpha["q3"].get<double>(), alpha["max"].get<double>());
  EXPECT_LE(alpha["max"].get<double>(), 0.5);
  EXPECT_FALSE(bytes(dir / "default.pfm").empty());
  EXPECT_NE(bytes(dir / "default.pfm"), bytes(dir / "scaled.pfm"));
  // The default length is the scene's (its bounding radius over sqrt(3)), not the paper's
  // literal 1, on this box in millimetres.
  ASSERT_EQ(0, test::run_command(emlt_cmd(lin + (dir / "length-one.pfm").string() +
                                          " --ensemble-similarity-length 1")));
  EXPECT_NE(bytes(dir / "default.pfm"), bytes(dir / "length-one.pfm"));
  expect_clean_failure(lin + (dir / "o.exr").string() + " --ensemble-similarity-length -1",
                       "ensemble-similarity-length", dir / "o.exr");
  // The anisotropic kernel's fallback: the paper's vMF or the plane Gaussian; about a third
  // of the fits fall back, so the choice changes the image.
  const std::string ani = "render " + cornell() +
                          " --integrator emlt --mutations emlt-ani --mpp 8 --bootstrap 5000"
                          " --width 16 --height 16 --ensemble-size 32 --quiet -o ";
  ASSERT_EQ(0, test::run_command(emlt_cmd(ani + (dir / "vmf.pfm").string())));
  ASSERT_EQ(0, test::run_command(
                   emlt_cmd(ani + (dir / "vmf2.pfm").string() + " --ensemble-aniso-fallback vmf")));
  ASSERT_EQ(0, test::run_command(emlt_cmd(ani + (dir / "plane.pfm").string() +
                                          " --ensemble-aniso-fallback plane")));
  EXPECT_EQ(bytes(dir / "vmf.pfm"), bytes(dir / "vmf2.pfm"));
  EXPECT_NE(bytes(dir / "vmf.pfm"), bytes(dir / "plane.pfm"));
  expect_clean_failure(ani + (dir / "o.exr").string() + " --ensemble-aniso-fallback gaussian",
                       "ensemble-aniso-fallback", dir / "o.exr");
  // How Υ is chosen, what α is computed from, and the anisotropic covariance scale each
  // change the image; bad values are refused.
  const std::vector<std::array<std::string, 3>> variants = {
      {lin, "default.pfm", "--ensemble-guides nearby"},
      {lin, "default.pfm", "--ensemble-alpha-from ensemble"},
      {ani, "vmf.pfm", "--ensemble-aniso-scale 0.5"},
      {ani, "vmf.pfm", "--ensemble-aniso-multiscale 0.01"}};
  for (const auto& [command, reference, flag] : variants) {
    const fs::path out = dir / "variant.pfm";
    ASSERT_EQ(0, test::run_command(emlt_cmd(command + out.string() + " " + flag))) << flag;
    EXPECT_NE(bytes(dir / reference), bytes(out)) << flag;
  }
  expect_clean_failure(ani + (dir / "o.exr").string() + " --ensemble-guides nearest",
                       "ensemble-guides", dir / "o.exr");
  expect_clean_failure(ani + (dir / "o.exr").string() + " --ensemble-alpha-from y",
                       "ensemble-alpha-from", dir / "o.exr");
  expect_clean_failure(ani + (dir / "o.exr").string() + " --ensemble-aniso-scale -1",
                       "ensemble-aniso-scale", dir / "o.exr");
  expect_clean_failure(ani + (dir / "o.exr").string() + " --ensemble-aniso-multiscale 0",
                       "ensemble-aniso-multiscale", dir / "o.exr");
  // Absurd ensembles are refused before anything is allocated or written.
  expect_clean_failure("render " + cornell() + " -o " + (dir / "o.exr").string() +
                           " --integrator emlt --ensemble-size 100000000",
                       "ensemble-size", dir / "o.exr");
  // The map needs an MCMC integrator.
  expect_clean_failure("render " + cornell() + " -o " + (dir / "o.exr").string() +
                           " --integrator pt --aniso-map " + (dir / "a.png").string(),
                       "--aniso-map", dir / "o.exr");
}

namespace {
std::vector<std::vector<std::string>> read_csv(const fs::path& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}
}  // namespace

TEST(CliConvergenceLog, RowsAtPowersOfTwoAndTheImageIsUnchanged) {
  const fs::path dir = test::scratch_dir("log");
  const std::string common =
      " --width 16 --height 16 --quiet --spp 8 --mpp 8 --bootstrap 5000 --mutations bidir=1";
  ASSERT_EQ(
      0, test::run_command(emlt_cmd("render " + cornell() + " -o " + (dir / "ref.pfm").string() +
                                    " --integrator bdpt --spp 64 --width 16 --height 16 --quiet")));
  for (const std::string integrator : {"pt", "bdpt", "mlt"}) {
    const fs::path plain = dir / (integrator + "-plain.pfm"),
                   logged = dir / (integrator + "-logged.pfm");
    const fs::path log = dir / (integrator + ".csv");
    ASSERT_EQ(0, test::run_command(emlt_cmd("render " + cornell() + " -o " + plain.string() +
                                            " --integrator " + integrator + common)));
    std::string text;
    ASSERT_EQ(0,
              test::run_command(emlt_cmd("render " + cornell() + " -o " + logged.string() +
                                         " --integrator " + integrator + common + " --reference " +
                                         (dir / "ref.pfm").string() + " --log " + log.string()),
                                &text))
        << text;
    // Snapshots never disturb the render.
    const Image a = read_image(plain.string()), b = read_image(logged.string());
    EXPECT_EQ(0, std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Rgb)))
        << integrator;
    const auto rows = read_csv(log);
    ASSERT_EQ(rows.size(), 5u) << integrator;  // header + 1, 2, 4, 8
    EXPECT_EQ(rows[0][0], "per_pixel");
    for (int i = 1; i <= 4; ++i)
      EXPECT_EQ(std::stod(rows[size_t(i)][0]), double(1 << (i - 1))) << integrator;
    if (integrator == "mlt") {
      EXPECT_EQ(rows[0].back(), "acceptance_bidir");
    }
    // The last row is the final image's error.
    const ImageMetrics m = compare_images(read_image((dir / "ref.pfm").string()), b);
    EXPECT_NEAR(std::stod(rows[4][2]), m.mse, 1e-6 * m.mse) << integrator;
    EXPECT_NEAR(std::stod(rows[4][5]), m.mean_ratio, 1e-5) << integrator;
  }
  // A log needs a reference of the right size.
  expect_clean_failure("render " + cornell() + " -o " + (dir / "o.exr").string() + " --log " +
                           (dir / "x.csv").string(),
                       "--reference", dir / "o.exr");
  expect_clean_failure("render " + cornell() + " -o " + (dir / "o.exr").string() +
                           " --width 8 --height 8 --reference " + (dir / "ref.pfm").string() +
                           " --log " + (dir / "x.csv").string(),
                       "ref.pfm", dir / "o.exr");
}
