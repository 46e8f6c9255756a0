// Maintainer tool: prints the RGB (eta, k) that Mitsuba 0.6 built in RGB mode
// (SPECTRUM_SAMPLES=3) gives each named conductor, as the lines of the table in
// src/scene/materials/conductor_presets.cpp.
//
// Usage: emlt_conductor_presets <dir>
//   <dir> is a Mitsuba 0.6 checkout or distribution (its data/ior is used) or a directory
//   holding the <name>.eta.spd / <name>.k.spd pairs themselves. From a bare git mirror:
//     mkdir /tmp/mts && git --git-dir=<mirror> archive <rev> data/ior | tar -x -C /tmp/mts
//     emlt_conductor_presets /tmp/mts
// Build: cmake --build <build dir> --target emlt_conductor_presets (not part of `all`).
// Paste the lines over the generated part of the table, then clang-format the file.
//
// How Mitsuba turns material="<name>" into RGB: it reads data/ior/<name>.eta.spd and
// <name>.k.spd as piecewise-linear spectra, used as they are (no zero extension: zero
// outside the measured range, a step there, no clamping of the data), converts each to
// CIE XYZ over 360-830 nm normalised by ∫ȳ, then to linear Rec.709 RGB, and does not
// clamp negative results. (Only the conductor plugins then divide both by the exterior IOR,
// extEta, "air" = 1.000277 by default; that happens in the scene loader, not in the table.)
// Here spectrum::to_xyz integrates exactly in double precision where Mitsuba uses an
// adaptive single-precision Gauss-Lobatto quadrature; for all 71 materials of Mitsuba 0.6 the
// results agree with Mitsuba's own to 3.3e-5 absolute, 8e-6 relative.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "emlt/scene/spectrum.h"

namespace fs = std::filesystem;
using namespace emlt;

namespace {

Rgb spd_to_rgb(const fs::path& file) {
  const DVec3 rgb =
      spectrum::xyz_to_linear_rgb(spectrum::to_xyz(spectrum::read_spd(file.string())));
  return Rgb(float(rgb.x), float(rgb.y), float(rgb.z));
}

// A float literal with 7 significant digits ("1.f", not "1f", which is no literal).
std::string number(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.7g", double(v));
  const bool has_point = std::string_view(text).find_first_of(".e") != std::string_view::npos;
  return std::string(text) + (has_point ? "f" : ".f");
}

std::string triple(const Rgb& c) {
  std::string s = "{";
  for (int i = 0; i < 3; ++i) s.append(i ? ", " : "").append(number(c[i]));
  return s.append("}");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <Mitsuba checkout, or its data/ior directory>\n", argv[0]);
    return 2;
  }
  fs::path dir = argv[1];
  if (fs::is_directory(dir / "data" / "ior")) dir = dir / "data" / "ior";
  try {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string file = entry.path().filename().string();
      const std::string suffix = ".eta.spd";
      if (file.size() > suffix.size() && file.ends_with(suffix)) {
        const std::string name = file.substr(0, file.size() - suffix.size());
        if (fs::exists(dir / (name + ".k.spd"))) names.push_back(name);
      }
    }
    if (names.empty()) {
      std::fprintf(stderr, "%s: no <name>.eta.spd / <name>.k.spd pairs\n", dir.c_str());
      return 1;
    }
    std::sort(names.begin(), names.end());
    std::printf("    // %zu materials from %s\n", names.size(), dir.c_str());
    for (const std::string& name : names) {
      const Rgb eta = spd_to_rgb(dir / (name + ".eta.spd"));
      const Rgb k = spd_to_rgb(dir / (name + ".k.spd"));
      std::printf("    {\"%s\", %s, %s},\n", name.c_str(), triple(eta).c_str(), triple(k).c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
