// Spectra as Mitsuba 0.6 reads them in RGB mode (include/emlt/scene/spectrum.h). The
// expected RGB values below were rendered by Mitsuba 0.6 itself (RGB build, a constant
// environment emitter with the spectrum as its radiance, seen directly, PFM output). Mitsuba
// averages with an adaptive single-precision Gauss-Lobatto quadrature that is accurate to a
// few 1e-5 relative, so those figures are matched to 1e-4; the exact values (an independent
// double-precision computation) are matched to 1e-6.
#include "emlt/scene/spectrum.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "emlt/core/error.h"
#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

using test::write_file;

// The classic Cornell box's measured reflectances (400-700 nm every 4 nm) and its light
// (a public scene; only the numbers are used).
const char* kCboxWhite =
    "400:0.343, 404:0.445, 408:0.551, 412:0.624, 416:0.665, 420:0.687, 424:0.708, 428:0.723, "
    "432:0.715, 436:0.71, 440:0.745, 444:0.758, 448:0.739, 452:0.767, 456:0.777, 460:0.765, "
    "464:0.751, 468:0.745, 472:0.748, 476:0.729, 480:0.745, 484:0.757, 488:0.753, 492:0.75, "
    "496:0.746, 500:0.747, 504:0.735, 508:0.732, 512:0.739, 516:0.734, 520:0.725, 524:0.721, "
    "528:0.733, 532:0.725, 536:0.732, 540:0.743, 544:0.744, 548:0.748, 552:0.728, 556:0.716, "
    "560:0.733, 564:0.726, 568:0.713, 572:0.74, 576:0.754, 580:0.764, 584:0.752, 588:0.736, "
    "592:0.734, 596:0.741, 600:0.74, 604:0.732, 608:0.745, 612:0.755, 616:0.751, 620:0.744, "
    "624:0.731, 628:0.733, 632:0.744, 636:0.731, 640:0.712, 644:0.708, 648:0.729, 652:0.73, "
    "656:0.727, 660:0.707, 664:0.703, 668:0.729, 672:0.75, 676:0.76, 680:0.751, 684:0.739, "
    "688:0.724, 692:0.73, 696:0.74, 700:0.737";
const char* kCboxRed =
    "400:0.04, 404:0.046, 408:0.048, 412:0.053, 416:0.049, 420:0.05, 424:0.053, 428:0.055, "
    "432:0.057, 436:0.056, 440:0.059, 444:0.057, 448:0.061, 452:0.061, 456:0.06, 460:0.062, "
    "464:0.062, 468:0.062, 472:0.061, 476:0.062, 480:0.06, 484:0.059, 488:0.057, 492:0.058, "
    "496:0.058, 500:0.058, 504:0.056, 508:0.055, 512:0.056, 516:0.059, 520:0.057, 524:0.055, "
    "528:0.059, 532:0.059, 536:0.058, 540:0.059, 544:0.061, 548:0.061, 552:0.063, 556:0.063, "
    "560:0.067, 564:0.068, 568:0.072, 572:0.08, 576:0.09, 580:0.099, 584:0.124, 588:0.154, "
    "592:0.192, 596:0.255, 600:0.287, 604:0.349, 608:0.402, 612:0.443, 616:0.487, 620:0.513, "
    "624:0.558, 628:0.584, 632:0.62, 636:0.606, 640:0.609, 644:0.651, 648:0.612, 652:0.61, "
    "656:0.65, 660:0.638, 664:0.627, 668:0.62, 672:0.63, 676:0.628, 680:0.642, 684:0.639, "
    "688:0.657, 692:0.639, 696:0.635, 700:0.642";
const char* kCboxGreen =
    "400:0.092, 404:0.096, 408:0.098, 412:0.097, 416:0.098, 420:0.095, 424:0.095, 428:0.097, "
    "432:0.095, 436:0.094, 440:0.097, 444:0.098, 448:0.096, 452:0.101, 456:0.103, 460:0.104, "
    "464:0.107, 468:0.109, 472:0.112, 476:0.115, 480:0.125, 484:0.14, 488:0.16, 492:0.187, "
    "496:0.229, 500:0.285, 504:0.343, 508:0.39, 512:0.435, 516:0.464, 520:0.472, 524:0.476, "
    "528:0.481, 532:0.462, 536:0.447, 540:0.441, 544:0.426, 548:0.406, 552:0.373, 556:0.347, "
    "560:0.337, 564:0.314, 568:0.285, 572:0.277, 576:0.266, 580:0.25, 584:0.23, 588:0.207, "
    "592:0.186, 596:0.171, 600:0.16, 604:0.148, 608:0.141, 612:0.136, 616:0.13, 620:0.126, "
    "624:0.123, 628:0.121, 632:0.122, 636:0.119, 640:0.114, 644:0.115, 648:0.117, 652:0.117, "
    "656:0.118, 660:0.12, 664:0.122, 668:0.128, 672:0.132, 676:0.139, 680:0.144, 684:0.146, "
    "688:0.15, 692:0.152, 696:0.157, 700:0.159";
const char* kCboxLight = "400:0, 500:8, 600:15.6, 700:18.4";

spectrum::PiecewiseLinear parse_pairs(const std::string& text) {
  std::vector<float> wavelengths, values;
  std::string token;
  std::istringstream in(text);
  while (std::getline(in, token, ',')) {
    const size_t colon = token.find(':');
    wavelengths.push_back(std::stof(token.substr(0, colon)));
    values.push_back(std::stof(token.substr(colon + 1)));
  }
  return spectrum::make_piecewise_linear(wavelengths, values);
}

Rgb sampled(const std::string& text) { return spectrum::sampled_to_rgb(parse_pairs(text)); }

void expect_rgb_near(const Rgb& actual, const Rgb& expected, double relative) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(actual[c], expected[c], relative * std::abs(expected[c]) + 1e-12)
        << "channel " << c << " of (" << actual.x << ", " << actual.y << ", " << actual.z
        << ") against (" << expected.x << ", " << expected.y << ", " << expected.z << ")";
}

// A scene whose constant environment emitter has `colour` (an element named "radiance")
// on line 5 of the file, and nothing else to warn about.
std::string scene_with(const std::filesystem::path& dir, const std::string& colour) {
  return write_file(dir, "scene.xml",
                    "<scene version=\"0.6.0\">\n"
                    "  <sensor type=\"perspective\"/>\n"
                    "  <shape type=\"sphere\"><bsdf type=\"diffuse\"/></shape>\n"
                    "  <emitter type=\"constant\">\n    " +
                        colour + "\n  </emitter>\n</scene>\n");
}

Rgb radiance_of(const std::string& colour, std::vector<std::string>* warnings = nullptr) {
  const auto dir = test::scratch_dir("colour");
  const SceneDescription desc = load_scene_description(scene_with(dir, colour));
  if (warnings) *warnings = desc.warnings;
  return desc.environment.radiance;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

std::string load_error(const std::string& colour) {
  const auto dir = test::scratch_dir("bad");
  return error_of([&] { load_scene_description(scene_with(dir, colour)); });
}

}  // namespace

TEST(SpectrumConversion, ConstantSpectrumHasUnitLuminanceAndEqualEnergyColour) {
  // s ≡ 1 over the whole CIE range: Y is exactly 1 (the normalisation), and the equal-
  // energy white is not sRGB white (no white-point adaptation in Mitsuba's conversion).
  const spectrum::PiecewiseLinear flat = parse_pairs("300:1, 900:1");
  const DVec3 xyz = spectrum::to_xyz(flat);
  EXPECT_NEAR(xyz.y, 1.0, 1e-12);
  const DVec3 rgb = spectrum::xyz_to_linear_rgb(xyz);
  EXPECT_NEAR(rgb.x, 1.2048863697, 1e-6);
  EXPECT_NEAR(rgb.y, 0.9482281710, 1e-6);
  EXPECT_NEAR(rgb.z, 0.9092664066, 1e-6);
}

TEST(SpectrumConversion, CornellBoxSpectraMatchMitsuba) {
  expect_rgb_near(sampled(kCboxWhite), Rgb(0.88588357f, 0.69884831f, 0.6667425f), 1e-4);
  expect_rgb_near(sampled(kCboxRed), Rgb(0.57014102f, 0.042777061f, 0.044416524f), 1e-4);
  expect_rgb_near(sampled(kCboxGreen), Rgb(0.10491241f, 0.37838697f, 0.076245151f), 1e-4);
  expect_rgb_near(sampled(kCboxLight), Rgb(20.77977f, 10.847587f, 2.7705536f), 1e-4);
  expect_rgb_near(sampled("400:0.78, 500:0.78, 600:0.78, 700:0.78"),
                  Rgb(0.93929338f, 0.73971754f, 0.70887715f), 1e-4);
  // Independent double-precision values of the exact integrals.
  expect_rgb_near(sampled(kCboxWhite), Rgb(0.885887191f, 0.698845771f, 0.666743453f), 1e-6);
  expect_rgb_near(sampled(kCboxLight), Rgb(20.779763f, 10.8475814f, 2.77055491f), 1e-6);
}

TEST(SpectrumConversion, SamplesReachingPastTheCieTablesMatchMitsuba) {
  // 300-900 nm: the parts outside 360-830 nm do not count.
  expect_rgb_near(sampled("300:1, 900:2"), Rgb(1.8780421f, 1.3334011f, 1.1175658f), 1e-4);
  expect_rgb_near(sampled("300:1, 900:2"), Rgb(1.87805085f, 1.3333974f, 1.11756743f), 1e-6);
}

TEST(SpectrumConversion, EndsFallToZeroOverOneAverageSpacing) {
  // 500-520 nm every 10 nm: zero at 490 and 530, linear in between, zero beyond.
  const Rgb extended = sampled("500:1, 510:1, 520:1");
  expect_rgb_near(extended, sampled("490:0, 500:1, 510:1, 520:1, 530:0"), 1e-7);
  // An end that is already zero is not extended.
  expect_rgb_near(sampled("500:0, 510:1, 520:0"), sampled("490:0, 500:0, 510:1, 520:0"), 1e-7);
  // The average spacing, not the last gap: (530 - 500) / 2 = 15 nm.
  expect_rgb_near(sampled("500:1, 502:1, 530:1"),
                  sampled("485:0, 500:1, 502:1, 530:1, 545:0"), 1e-7);
}

TEST(SpectrumConversion, NegativeComponentsAreClampedToZero) {
  // Mostly violet with a negative lobe: R and B of the raw conversion are negative.
  const spectrum::PiecewiseLinear s = parse_pairs("400:1, 450:-0.5, 500:0, 620:0, 700:0");
  spectrum::PiecewiseLinear extended = s;
  spectrum::zero_extend(extended);
  const DVec3 raw = spectrum::xyz_to_linear_rgb(spectrum::to_xyz(extended));
  EXPECT_LT(raw.y, 0.0);
  EXPECT_LT(raw.z, 0.0);
  const Rgb rgb = spectrum::sampled_to_rgb(s);
  EXPECT_EQ(rgb.y, 0.0f);
  EXPECT_EQ(rgb.z, 0.0f);
  EXPECT_NEAR(rgb.x, 0.01311369, 1e-4 * 0.01311369);  // Mitsuba: 0.01311369 0 0
}

TEST(SpectrumConversion, BlackBodyMatchesMitsuba) {
  // Planck's law in W m^-2 nm^-1 sr^-1: 6500 K at 500 nm.
  EXPECT_NEAR(spectrum::planck(500.0, 6500.0), 46097.1688, 1e-3);
  expect_rgb_near(spectrum::blackbody_to_rgb(3000.0, 1e-4),
                  Rgb(0.073312782f, 0.034956448f, 0.011268668f), 1e-4);
  expect_rgb_near(spectrum::blackbody_to_rgb(6500.0, 1e-5),
                  Rgb(0.43919018f, 0.41407683f, 0.43584105f), 1e-4);
  const Rgb deep_red = spectrum::blackbody_to_rgb(1000.0);  // B clamped before scaling
  EXPECT_NEAR(deep_red.x, 0.00016934429, 1e-4 * 0.00016934429);
  EXPECT_NEAR(deep_red.y, 1.4586136e-06, 1e-4 * 1.4586136e-06);
  EXPECT_EQ(deep_red.z, 0.0f);
  expect_rgb_near(spectrum::blackbody_to_rgb(1000.0, -2.0), deep_red * -2.0f, 1e-7);
}

TEST(SpectrumConversion, MalformedSpectraAreRejected) {
  EXPECT_NE(error_of([] { spectrum::make_piecewise_linear({500, 400}, {1, 1}); })
                .find("wavelengths must increase"),
            std::string::npos);
  EXPECT_NE(error_of([] { spectrum::sampled_to_rgb(parse_pairs("500:1")); }).find("2 samples"),
            std::string::npos);
  EXPECT_NE(error_of([] { spectrum::blackbody_to_rgb(-300.0); }).find("> 0 K"),
            std::string::npos);
  EXPECT_NE(error_of([] { spectrum::blackbody_to_rgb(0.0); }).find("> 0 K"), std::string::npos);
}

TEST(SpectrumXml, EveryColourFormMeansWhatMitsubaRgbModeLoads) {
  std::vector<std::string> warnings;
  // One value: grey, whatever the intent (D65 is flat 1 in RGB mode).
  EXPECT_EQ(radiance_of(R"(<spectrum name="radiance" value="0.5"/>)", &warnings), Rgb(0.5f));
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(radiance_of(R"(<spectrum name="radiance" value="0.5" intent="Reflectance"/>)"),
            Rgb(0.5f));
  // Three values: one per spectral sample, i.e. linear RGB, unchanged.
  EXPECT_EQ(radiance_of(R"(<spectrum name="radiance" value="0.1, 0.2, 0.3"/>)"),
            Rgb(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(radiance_of(R"(<spectrum name="radiance" value="0.1 0.2 0.3"/>)"),
            Rgb(0.1f, 0.2f, 0.3f));
  // <rgb>: linear, and a #rrggbb is byte / 255 without gamma decoding.
  EXPECT_EQ(radiance_of(R"(<rgb name="radiance" value="0.2, 0.4, 0.6"/>)"), Rgb(0.2f, 0.4f, 0.6f));
  EXPECT_EQ(radiance_of(R"(<rgb name="radiance" value="#336699"/>)"), Rgb(0.2f, 0.4f, 0.6f));
  EXPECT_EQ(radiance_of(R"(<rgb name="radiance" value="0.25" intent="illuminant"/>)"),
            Rgb(0.25f));
  // <srgb>: gamma-decoded, hex or numbers (Mitsuba's figures).
  expect_rgb_near(radiance_of(R"(<srgb name="radiance" value="#336699"/>)"),
                  Rgb(0.033104759f, 0.13286832f, 0.31854674f), 1e-6);
  expect_rgb_near(radiance_of(R"(<srgb name="radiance" value="0.02, 0.5, 0.9"/>)"),
                  Rgb(0.0015479876f, 0.21404114f, 0.78741223f), 1e-6);
  expect_rgb_near(radiance_of(R"(<srgb name="radiance" value="0.5"/>)"), Rgb(0.21404114f), 1e-6);
  // Wavelength:value lists.
  const Rgb white = sampled(kCboxWhite);
  EXPECT_EQ(radiance_of(std::string(R"(<spectrum name="radiance" value=")") + kCboxWhite +
                            "\"/>",
                        &warnings),
            white);
  EXPECT_TRUE(warnings.empty());
  // Black body, temperature with or without its unit.
  expect_rgb_near(
      radiance_of(R"(<blackbody name="radiance" temperature="6500K" scale="1e-5"/>)", &warnings),
      Rgb(0.43919018f, 0.41407683f, 0.43584105f), 1e-4);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(radiance_of(R"(<blackbody name="radiance" temperature=" 3000 "/>)"),
            spectrum::blackbody_to_rgb(3000.0));
}

TEST(SpectrumXml, SpectrumFileResolvesAgainstTheSceneFile) {
  const auto dir = test::scratch_dir("spd");
  std::filesystem::create_directories(dir / "data");
  // Mitsuba's format: comments, blank lines, "wavelength value" (extra columns ignored).
  std::string spd = "# Cornell box white\n\n";
  std::istringstream pairs(kCboxWhite);
  std::string pair;
  while (std::getline(pairs, pair, ',')) {
    const size_t colon = pair.find(':');
    spd += pair.substr(0, colon) + "\t" + pair.substr(colon + 1) + "  extra\n";
  }
  write_file(dir / "data", "white.spd", spd);
  const std::string xml =
      scene_with(dir, R"(<spectrum name="radiance" filename="data/white.spd"/>)");
  const SceneDescription desc = load_scene_description(xml);
  EXPECT_TRUE(desc.warnings.empty());
  EXPECT_EQ(desc.environment.radiance, sampled(kCboxWhite));
  expect_rgb_near(desc.environment.radiance, Rgb(0.88588357f, 0.69884831f, 0.6667425f), 1e-4);
}

TEST(SpectrumXml, MalformedColoursNameTheFileAndLine) {
  const auto has = [](const std::string& error, const std::string& part) {
    return error.find("scene.xml: line 5: ") != std::string::npos &&
           error.find(part) != std::string::npos;
  };
  EXPECT_PRED2(has, load_error(R"(<spectrum name="radiance" value="500:1, 400:2"/>)"),
               "wavelengths must increase");
  EXPECT_PRED2(has, load_error(R"(<spectrum name="radiance" value="400:1, 500"/>)"),
               "'500' is not a wavelength:value pair");
  EXPECT_PRED2(has, load_error(R"(<spectrum name="radiance" value="400:1:2, 500:1"/>)"),
               "is not a wavelength:value pair");
  EXPECT_PRED2(has, load_error(R"(<spectrum name="radiance" value="500:1"/>)"), "2 samples");
  EXPECT_PRED2(has, load_error(R"(<spectrum name="radiance" value="0.1, 0.2"/>)"),
               "not a valid <spectrum> value");
  EXPECT_PRED2(has, load_error(R"(<spectrum name="radiance" filename="missing.spd"/>)"),
               "missing.spd: cannot be read");
  EXPECT_PRED2(has, load_error(R"(<spectrum name="radiance"/>)"), "one of 'value' and 'filename'");
  EXPECT_PRED2(has, load_error(R"(<spectrum name="radiance" value="0.5" intent="light"/>)"),
               "invalid intent");
  EXPECT_PRED2(has,
               load_error(R"(<spectrum name="radiance" value="400:1, 500:1" intent="illuminant"/>)"),
               "single-valued");
  EXPECT_PRED2(has, load_error(R"(<blackbody name="radiance" temperature="-300"/>)"), "> 0 K");
  EXPECT_PRED2(has, load_error(R"(<rgb name="radiance" value="#33669g"/>)"), "#rrggbb");

  // Problems inside a .spd file name it and its line too.
  const auto dir = test::scratch_dir("badspd");
  write_file(dir, "down.spd", "# falls\n400 1\n500 2\n450 3\n");
  write_file(dir, "junk.spd", "400 1\nfour-hundred 2\n");
  const std::string down =
      error_of([&] { load_scene_description(scene_with(dir, R"(<spectrum name="radiance" filename="down.spd"/>)")); });
  EXPECT_PRED2(has, down, "down.spd: line 4: wavelengths must increase");
  const std::string junk =
      error_of([&] { load_scene_description(scene_with(dir, R"(<spectrum name="radiance" filename="junk.spd"/>)")); });
  EXPECT_PRED2(has, junk, "junk.spd: line 2: 'four-hundred 2' is not a 'wavelength value' pair");
}
