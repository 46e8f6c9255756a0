#include "emlt/scene/conductor_presets.h"

#include <array>

namespace emlt {
namespace {

struct ConductorPreset {
  const char* name;
  Rgb eta, k;
};

// Spectral n, k sampled at 650 nm (R), 550 nm (G) and 450 nm (B), rounded, from published
// measurements: Cu, Ag, Au from Johnson & Christy 1972; Al from Rakic 1995; Cr from
// Johnson & Christy 1974. Point samples rather than integrals against the RGB matching
// functions, so colours are close to, not identical with, Mitsuba's spectral renders.
// Normal-incidence reflectances these give: Cu (0.94, 0.62, 0.55), Ag (0.97, 0.96, 0.93),
// Au (0.94, 0.79, 0.39), Al (0.91, 0.92, 0.92), Cr (0.55, 0.56, 0.56).
const std::array<ConductorPreset, 6> kPresets = {{
    {"Cu", {0.21f, 1.00f, 1.17f}, {3.67f, 2.58f, 2.40f}},
    {"Ag", {0.15f, 0.12f, 0.14f}, {4.20f, 3.40f, 2.60f}},
    {"Au", {0.166f, 0.43f, 1.50f}, {3.15f, 2.45f, 1.88f}},
    {"Al", {1.49f, 0.96f, 0.62f}, {7.82f, 6.69f, 5.47f}},
    {"Cr", {3.20f, 2.90f, 2.10f}, {3.30f, 3.30f, 3.10f}},
    // Purely imaginary IOR: |r_s| = |r_p| = 1 exactly, i.e. a perfect mirror.
    {"none", {0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}},
}};

}  // namespace

bool conductor_preset(const std::string& name, Rgb* eta, Rgb* k) {
  for (const auto& preset : kPresets) {
    if (name == preset.name) {
      if (eta) *eta = preset.eta;
      if (k) *k = preset.k;
      return true;
    }
  }
  return false;
}

}  // namespace emlt
