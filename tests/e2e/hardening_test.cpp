// Bad numbers never get through: non-finite geometry is
// dropped with a counted warning (refused by --strict), non-finite scene parameters and
// absurd sizes are one-line errors, and every numeric flag states its range in words.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>

#include <sys/stat.h>

#include "support/cli_checks.h"
#include "support/test_support.h"

using namespace emlt;
using test::count_lines;
using test::emlt_cmd;
namespace fs = std::filesystem;

namespace {

void write_file(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// A failure as a user sees it (support/cli_checks.h: non-zero exit, one line naming
// `must_mention`, no output file), and quickly: nothing was allocated for the absurd size
// first.
void expect_clean_failure(const std::string& args, const std::string& must_mention,
                          const fs::path& output) {
  const auto start = std::chrono::steady_clock::now();
  test::expect_clean_failure(args, must_mention, output);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 10.0) << args;
}

// The scene around a mesh: a JSON camera looking at the mesh, which emits.
void write_json_scene(const fs::path& path, const std::string& mesh_file) {
  write_file(path, R"({"camera": {"lookat": {"origin": [0,0,-4], "target": [0,0,0], "up": [0,1,0]},
    "fov": 40, "width": 8, "height": 8},
    "shapes": [{"type": "obj", "file": ")" + mesh_file + R"(", "emission": [1,1,1]}]})");
}

void write_xml_scene(const fs::path& path, const std::string& ply_file) {
  write_file(path, R"(<scene version="0.6.0">
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,-4" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
  <shape type="ply"><string name="filename" value=")" + ply_file + R"("/>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>
)");
}

std::string ascii_ply(const std::string& vertices, int vertex_count, const std::string& faces,
                      const std::string& face_count) {
  return "ply\nformat ascii 1.0\nelement vertex " + std::to_string(vertex_count) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + face_count +
         "\nproperty list uchar int vertex_indices\nend_header\n" + vertices + faces;
}

}  // namespace

// A quad and a fan of three triangles around a NaN vertex: the three are dropped, the
// quad renders.
TEST(NonFiniteGeometry, ObjNanVertexDropsItsTrianglesWithACountedWarning) {
  const fs::path dir = test::scratch_dir("nonfinite-obj");
  write_file(dir / "mesh.obj",
             "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv nan 0 0\n"
             "f 1 2 3\nf 1 3 4\nf 1 2 5\nf 2 3 5\nf 3 4 5\n");
  write_json_scene(dir / "s.json", "mesh.obj");
  const fs::path out = dir / "o.pfm";
  std::string text;
  ASSERT_EQ(0, test::run_command(emlt_cmd("render " + (dir / "s.json").string() + " -o " +
                                          out.string() + " --spp 1 --quiet"), &text)) << text;
  EXPECT_NE(text.find("mesh.obj: 3 triangles with non-finite vertices dropped"), std::string::npos)
      << text;
  EXPECT_TRUE(fs::exists(out));
  ASSERT_EQ(0, test::run_command(emlt_cmd("info " + (dir / "s.json").string()), &text)) << text;
  EXPECT_NE(text.find("triangles    2 "), std::string::npos) << text;
  EXPECT_NE(text.find("verdict      unsupported: 1 item"), std::string::npos) << text;

  fs::remove(out);
  expect_clean_failure("render --strict " + (dir / "s.json").string() + " -o " + out.string(),
                       "mesh.obj: 3 triangles with non-finite vertices dropped", out);
  expect_clean_failure("info --strict " + (dir / "s.json").string(), "refused by --strict", out);
}

// Texture coordinates and normals count too ("inf" and an overflowing 1e999 alike).
TEST(NonFiniteGeometry, ObjNonFiniteTexCoordsAndNormalsCount) {
  const fs::path dir = test::scratch_dir("nonfinite-obj-attributes");
  write_file(dir / "mesh.obj",
             "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
             "vt 0 0\nvt 1 0\nvt 1 1\nvt 1e999 1\nvn 0 0 -1\nvn inf 0 -1\n"
             "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\nf 1/1/2 3/3/1 4/3/1\n");
  write_file(dir / "s.json", R"({"camera": {"lookat": {"origin": [0,0,-4], "target": [0,0,0], "up": [0,1,0]},
    "fov": 40, "width": 8, "height": 8},
    "shapes": [{"type": "obj", "file": "mesh.obj", "smooth_normals": true, "emission": [1,1,1]}]})");
  std::string text;
  ASSERT_EQ(0, test::run_command(emlt_cmd("info " + (dir / "s.json").string()), &text)) << text;
  EXPECT_NE(text.find("mesh.obj: 2 triangles with non-finite vertices dropped"), std::string::npos)
      << text;
  EXPECT_NE(text.find("triangles    1 "), std::string::npos) << text;
}

TEST(NonFiniteGeometry, ObjWithNoFiniteTriangleIsAnError) {
  const fs::path dir = test::scratch_dir("nonfinite-obj-all");
  write_file(dir / "mesh.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 inf\nf 1 2 3\nf 2 3 4\n");
  write_json_scene(dir / "s.json", "mesh.obj");
  expect_clean_failure("render " + (dir / "s.json").string() + " -o " + (dir / "o.exr").string(),
                       "mesh.obj: every triangle (2) has a NaN or infinite vertex", dir / "o.exr");
}

TEST(NonFiniteGeometry, PlyInfiniteVertexDropsItsTrianglesAndStrictRefuses) {
  const fs::path dir = test::scratch_dir("nonfinite-ply");
  write_file(dir / "mesh.ply", ascii_ply("-1 -1 0\n1 -1 0\n1 1 0\n-1 1 inf\n", 4,
                                         "3 0 1 2\n3 0 2 3\n", "2"));
  write_xml_scene(dir / "s.xml", "mesh.ply");
  const fs::path out = dir / "o.pfm";
  std::string text;
  ASSERT_EQ(0, test::run_command(emlt_cmd("render " + (dir / "s.xml").string() + " -o " +
                                          out.string() + " --spp 1 --quiet"), &text)) << text;
  EXPECT_NE(text.find("mesh.ply: 1 triangles with non-finite vertices dropped"), std::string::npos)
      << text;
  EXPECT_TRUE(fs::exists(out));
  fs::remove(out);
  expect_clean_failure("render --strict " + (dir / "s.xml").string() + " -o " + out.string(),
                       "mesh.ply: 1 triangles with non-finite vertices dropped", out);

  write_file(dir / "all.ply", ascii_ply("-1 -1 nan\n1 -1 0\n1 1 0\n", 3, "3 0 1 2\n", "1"));
  write_xml_scene(dir / "all.xml", "all.ply");
  expect_clean_failure("render " + (dir / "all.xml").string() + " -o " + out.string(),
                       "all.ply: every triangle (1) has a NaN or infinite vertex", out);
}

// JSON has no NaN literal; numbers that overflow single precision are where a NaN or
// infinity gets in.
TEST(NonFiniteParameters, JsonTransformCameraAndRadianceAreErrorsNamingTheFile) {
  const fs::path dir = test::scratch_dir("nonfinite-json");
  const auto scene = [](const std::string& camera_extra, const std::string& shape_extra,
                        const std::string& radiance) {
    return R"({"camera": {"lookat": {"origin": [0,0,-4], "target": [0,0,0], "up": [0,1,0]},
      "width": 8, "height": 8)" + camera_extra + R"(},
      "shapes": [{"type": "rectangle", "emission": [1,1,1])" + shape_extra + R"(}],
      "environment": {"type": "constant", "radiance": )" + radiance + "}}";
  };
  const fs::path out = dir / "o.exr";
  struct Case {
    std::string name, camera, shape, radiance, mention;
  } cases[] = {
      {"transform", "", R"(, "transform": [{"scale": 1e39}])", "1",
       "transform.json: shapes[0].transform[0].scale: expected a finite number, not NaN"},
      {"overflow", "", R"(, "transform": [{"translate": [0, 1e999, 0]}])", "1", "overflow.json"},
      {"camera", R"(, "fov": 1e40)", "", "1", "camera.json: camera.fov: expected a finite number, not NaN"},
      {"radiance", "", "", "[1, 1e300, 1]",
       "radiance.json: environment.radiance: expected a finite number, not NaN"},
  };
  for (const Case& c : cases) {
    const fs::path file = dir / (c.name + ".json");
    write_file(file, scene(c.camera, c.shape, c.radiance));
    expect_clean_failure("render " + file.string() + " -o " + out.string(), c.mention, out);
  }
}

TEST(NonFiniteParameters, XmlTransformAndRadianceOverflowAreErrorsNamingFileAndLine) {
  const fs::path dir = test::scratch_dir("nonfinite-xml");
  const auto scene = [](const std::string& transform, const std::string& radiance) {
    return R"(<scene version="0.6.0">
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="toWorld">)" + transform + R"(<lookat origin="0,0,-4" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
  <shape type="rectangle"><emitter type="area">)" + radiance + R"(</emitter></shape>
</scene>
)";
  };
  const fs::path out = dir / "o.exr";
  write_file(dir / "t.xml", scene(R"(<scale value="1e30"/><scale value="1e30"/>)",
                                  R"(<rgb name="radiance" value="1"/>)"));
  expect_clean_failure("render " + (dir / "t.xml").string() + " -o " + out.string(),
                       "t.xml: line 3: transform overflows to NaN or infinite values", out);
  write_file(dir / "r.xml",
             scene("", R"(<blackbody name="radiance" temperature="6500" scale="3e38"/>)"));
  expect_clean_failure("render " + (dir / "r.xml").string() + " -o " + out.string(),
                       "r.xml: line 6: 'radiance' gives a NaN or infinite colour", out);
  write_file(dir / "n.xml", scene("", R"(<rgb name="radiance" value="nan"/>)"));
  expect_clean_failure("render " + (dir / "n.xml").string() + " -o " + out.string(),
                       "n.xml: line 6: 'nan' is not a finite number", out);
}

// Each range in words, the whole line exactly; no raw limit such as 1.79769e+308 or
// 16777216 (the old CLI::Range messages) appears.
TEST(ReadableRanges, EveryNumericFlagStatesItsRangeInWords) {
  const fs::path dir = test::scratch_dir("ranges");
  const std::string scene = test::source_path("scenes/cornell-box/scene.json");
  const fs::path out = dir / "o.exr";
  const std::pair<std::string, std::string> cases[] = {
      {"--mpp 0", "emlt: error: --mpp must be a positive number, at most 2^24 (about 16.8 million) "
                  "(got 0)\n"},
      {"--time -1", "emlt: error: --time must be a positive number of seconds, at most 30 days "
                    "(got -1)\n"},
      {"--threads 5000", "emlt: error: --threads must be 1..1024, or 0 for all cores (got 5000)\n"},
      {"--spp 1e18", "emlt: error: --spp must be a whole number from 1 to 2^24 (about 16.8 "
                     "million) (got 1e18)\n"},
      {"--spp abc", "emlt: error: --spp must be a whole number from 1 to 2^24 (about 16.8 "
                    "million) (got abc)\n"},
      {"--width 100000", "emlt: error: --width must be a whole number of pixels from 1 to 16384 "
                         "(got 100000)\n"},
      {"--ensemble-alpha 200", "emlt: error: --ensemble-alpha must be a number from 0 (adaptive) "
                               "to 100 (got 200)\n"},
      {"--bootstrap 1e18", "emlt: error: --bootstrap must be a whole number from 1 to 2^24 "
                           "(about 16.8 million) (got 1e18)\n"},
      {"--chains -1", "emlt: error: --chains must be 1 to 2^20 (about a million), or 0 to choose "
                      "from the budget (got -1)\n"},
      {"--ensemble-size 1e18", "emlt: error: --ensemble-size must be 1 to 131072, or 0 for the "
                               "default (got 1e18)\n"},
      {"--max-depth -2", "emlt: error: --max-depth must be a whole number from 0 to 100000, or -1 "
                         "for unlimited (got -2)\n"},
      {"--ensemble-similarity-length inf", "emlt: error: --ensemble-similarity-length must be a "
                                           "positive length, or 0 for the scene's own (got "
                                           "inf)\n"},
      {"--ensemble-aniso-scale 1e9", "emlt: error: --ensemble-aniso-scale must be a number from 0 "
                                     "(the default) to 100 (got 1e9)\n"},
      {"--ensemble-aniso-multiscale 2", "emlt: error: --ensemble-aniso-multiscale must be a number "
                                        "from 0.0001 to 1 (got 2)\n"},
  };
  const std::regex long_number("[0-9]{7,}");
  for (const auto& [flags, expected] : cases) {
    std::string text;
    const int status =
        test::run_command(emlt_cmd("render " + scene + " -o " + out.string() + " " + flags), &text);
    EXPECT_NE(status, 0) << flags;
    EXPECT_EQ(text, expected) << flags;
    EXPECT_FALSE(std::regex_search(text, long_number)) << text;
    EXPECT_FALSE(fs::exists(out));
  }
}

// A scene parameter that a flag also sets is refused past the same bound, in the same
// words, by both scene formats (naming the JSON key or the XML line), and the bound itself
// is accepted by both.
TEST(ReadableRanges, SceneParametersShareTheFlagsBoundsAndWords) {
  const fs::path dir = test::scratch_dir("scene-ranges");
  const fs::path out = dir / "o.exr";
  const std::string cornell = test::source_path("scenes/cornell-box/scene.json");
  struct Setting {
    std::string flag, json_key, xml_name, past, bound;
  } settings[] = {
      {"--width", "camera.width", "width", "16385", "16384"},
      {"--height", "camera.height", "height", "0", "1"},
      {"--spp", "integrator.spp", "sampleCount", "16777217", "16777216"},
      {"--max-depth", "integrator.max_depth", "maxDepth", "100001", "100000"},
      {"--max-depth", "integrator.max_depth", "maxDepth", "-2", "-1"},
      {"--rr-depth", "integrator.rr_depth", "rrDepth", "0", "1"},
  };
  // A scene of each format whose camera and integrator give every one of these settings,
  // `changed` (a JSON key or an XML name) at `value` and the others at ordinary values.
  const auto json_scene = [](const std::string& changed, const std::string& value) {
    const auto field = [&](const std::string& key, const std::string& ordinary) {
      return "\"" + key.substr(key.find('.') + 1) + "\": " + (key == changed ? value : ordinary);
    };
    return R"({"camera": {"lookat": {"origin": [0,0,-4], "target": [0,0,0], "up": [0,1,0]}, )" +
           field("camera.width", "8") + ", " + field("camera.height", "8") +
           R"(}, "integrator": {)" + field("integrator.spp", "1") + ", " +
           field("integrator.max_depth", "6") + ", " + field("integrator.rr_depth", "5") +
           R"(}, "shapes": [{"type": "rectangle", "emission": [1,1,1]}]})";
  };
  // The XML parameters are on lines 2 (integrator), 5 (sampler) and 6 (film).
  const auto xml_scene = [](const std::string& changed, const std::string& value) {
    const auto param = [&](const std::string& name, const std::string& ordinary) {
      return "<integer name=\"" + name + "\" value=\"" + (name == changed ? value : ordinary) +
             "\"/>";
    };
    return "<scene version=\"0.6.0\">\n<integrator type=\"path\">" + param("maxDepth", "6") +
           param("rrDepth", "5") + "</integrator>\n<sensor type=\"perspective\">\n" +
           "<transform name=\"toWorld\"><lookat origin=\"0,0,-4\" target=\"0,0,0\" "
           "up=\"0,1,0\"/></transform>\n<sampler type=\"independent\">" +
           param("sampleCount", "1") + "</sampler>\n<film type=\"hdrfilm\">" +
           param("width", "8") + param("height", "8") + "</film>\n</sensor>\n" +
           "<shape type=\"rectangle\"><emitter type=\"area\"><rgb name=\"radiance\" "
           "value=\"1\"/></emitter></shape>\n</scene>\n";
  };
  const std::regex long_number("[0-9]{7,}");
  for (const Setting& s : settings) {
    std::string flag_text;
    EXPECT_NE(test::run_command(emlt_cmd("render " + cornell + " -o " + out.string() + " " +
                                         s.flag + " " + s.past),
                                &flag_text),
              0);
    const std::string prefix = "emlt: error: " + s.flag + " must be ";
    const std::string suffix = " (got " + s.past + ")\n";
    ASSERT_EQ(flag_text.rfind(prefix, 0), 0u) << flag_text;
    ASSERT_GE(flag_text.size(), prefix.size() + suffix.size()) << flag_text;
    const std::string words =
        flag_text.substr(prefix.size(), flag_text.size() - prefix.size() - suffix.size());
    EXPECT_FALSE(std::regex_search(words, long_number)) << words;

    write_file(dir / "past.json", json_scene(s.json_key, s.past));
    expect_clean_failure("render " + (dir / "past.json").string() + " -o " + out.string(),
                         "past.json: " + s.json_key + ": must be " + words + suffix, out);
    write_file(dir / "past.xml", xml_scene(s.xml_name, s.past));
    const int line = s.xml_name == "sampleCount"                          ? 5
                     : s.xml_name == "width" || s.xml_name == "height" ? 6
                                                                         : 2;
    expect_clean_failure("render " + (dir / "past.xml").string() + " -o " + out.string(),
                         "past.xml: line " + std::to_string(line) + ": '" + s.xml_name +
                             "' must be " + words + suffix,
                         out);

    write_file(dir / "bound.json", json_scene(s.json_key, s.bound));
    write_file(dir / "bound.xml", xml_scene(s.xml_name, s.bound));
    for (const char* scene : {"bound.json", "bound.xml"}) {
      std::string text;
      EXPECT_EQ(test::run_command(emlt_cmd("info " + (dir / scene).string()), &text), 0)
          << scene << " " << s.xml_name << " = " << s.bound << ": " << text;
    }
  }
}

TEST(ResourceLimits, AbsurdSizesAreRefusedBeforeAnythingIsAllocated) {
  const fs::path dir = test::scratch_dir("limits");
  const fs::path out = dir / "o.exr";
  // A 10^6 x 10^6 film from a scene file (the flags stop at 16384).
  write_file(dir / "film.json", R"({"camera": {"width": 1000000, "height": 1000000},
    "shapes": [{"type": "rectangle", "emission": [1,1,1]}]})");
  expect_clean_failure("render " + (dir / "film.json").string() + " -o " + out.string(),
                       "film.json: camera.width: must be a whole number of pixels from 1 to 16384 "
                       "(got 1000000)", out);
  write_file(dir / "wide.json", R"({"camera": {"width": 1000000000000, "height": 8},
    "shapes": [{"type": "rectangle", "emission": [1,1,1]}]})");
  expect_clean_failure("render " + (dir / "wide.json").string() + " -o " + out.string(),
                       "wide.json: camera.width: expected an integer within +-2^31", out);
  write_file(dir / "spp.json", R"({"integrator": {"spp": 1000000000},
    "shapes": [{"type": "rectangle", "emission": [1,1,1]}]})");
  expect_clean_failure("render " + (dir / "spp.json").string() + " -o " + out.string(),
                       "spp.json: integrator.spp: must be a whole number from 1 to 2^24", out);
  expect_clean_failure("render " + (dir / "spp.json").string() + " -o " + out.string() +
                           " --spp 1e18",
                       "--spp must be a whole number from 1 to 2^24", out);

  // An image header claiming 100000 x 100000 texels (120 GB as float RGB), followed by
  // a few bytes: refused from the header, whichever reader.
  {
    std::ofstream pfm(dir / "huge.pfm", std::ios::binary);
    pfm << "PF\n100000 100000\n-1.0\n" << std::string(64, '\0');
  }
  const std::string claim =
      "huge.pfm: header claims 100000 x 100000 texels; images may have at most 65536 texels a "
      "side and 2^28 (about 268 million) in all";
  expect_clean_failure("compare " + (dir / "huge.pfm").string() + " " + (dir / "huge.pfm").string(),
                       claim, out);
  write_file(dir / "env.json", R"({"environment": {"type": "envmap", "file": "huge.pfm"},
    "shapes": [{"type": "rectangle"}]})");
  expect_clean_failure("render " + (dir / "env.json").string() + " -o " + out.string(), claim, out);

  // A PLY header claiming 10^12 faces in a file of a few bytes.
  write_file(dir / "huge.ply", ascii_ply("0 0 0\n1 0 0\n0 1 0\n", 3, "3 0 1 2\n", "1000000000000"));
  write_xml_scene(dir / "ply.xml", "huge.ply");
  expect_clean_failure("render " + (dir / "ply.xml").string() + " -o " + out.string(),
                       "huge.ply: header claims 1000000000000 face elements, more than the file's",
                       out);
}

// A FIFO named as a texture or a mesh is refused as the loader refuses any non-regular
// file, never read: a read would block for ever (the files a Mitsuba scene names are read
// ahead in tasks, and the loader's end waits for them). `timeout` turns a hang into a
// failure of this test instead of the suite's.
TEST(NotRegularFiles, FifoNamedAsTextureOrMeshIsAnErrorNotAHang) {
  const fs::path dir = test::scratch_dir("fifo");
  const fs::path fifo_png = dir / "texture.png", fifo_obj = dir / "mesh.obj";
  for (const fs::path& fifo : {fifo_png, fifo_obj}) {
    fs::remove(fifo);
    ASSERT_EQ(0, mkfifo(fifo.c_str(), 0600)) << fifo;
  }
  const std::string camera = R"(<sensor type="perspective"><float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,-4" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>)";
  write_file(dir / "texture.xml", R"(<scene version="0.6.0">)" + camera + R"(
  <shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance">
    <string name="filename" value="texture.png"/></texture></bsdf>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>)");
  write_file(dir / "mesh.xml", R"(<scene version="0.6.0">)" + camera + R"(
  <shape type="obj"><string name="filename" value="mesh.obj"/>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>)");
  for (const auto& [scene, name] :
       {std::pair{"texture.xml", "texture.png"}, std::pair{"mesh.xml", "mesh.obj"}}) {
    const fs::path out = dir / "o.exr";
    std::string text;
    const int status = test::run_command(
        "timeout 30 " + emlt_cmd("render " + (dir / scene).string() + " -o " + out.string()),
        &text);
    EXPECT_NE(status, 0) << scene;
    EXPECT_NE(status, 124) << scene << ": timed out (a blocking read)";
    EXPECT_EQ(count_lines(text), 1) << text;
    EXPECT_NE(text.find(name), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(out));
  }
}
