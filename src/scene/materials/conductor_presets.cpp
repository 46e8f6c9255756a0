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
// Added for issue 8, same wavelengths unless stated:
//   Fe  Johnson & Christy 1974 point samples (via refractiveindex.info); R0 (0.53, 0.53, 0.49).
//   Ti  Rakic et al. 1998 Lorentz-Drude fit (Appl. Opt. 37, 5271) evaluated at 650/550/450
//       nm (450 nm lies just outside the fit's 470 nm bound); R0 (0.58, 0.57, 0.59).
//   Ni, W, Mo, Ir, Rh, Be, TiN  Palik's handbook tables (the data Mitsuba 0.6 ships as
//       data/ior/*.spd) averaged over the R/G/B bands, rounded to three digits.
// Mitsuba's "<name>_palik" spellings map to the same entries.
const std::array<ConductorPreset, 15> kPresets = {{
    {"Cu", {0.21f, 1.00f, 1.17f}, {3.67f, 2.58f, 2.40f}},
    {"Ag", {0.15f, 0.12f, 0.14f}, {4.20f, 3.40f, 2.60f}},
    {"Au", {0.166f, 0.43f, 1.50f}, {3.15f, 2.45f, 1.88f}},
    {"Al", {1.49f, 0.96f, 0.62f}, {7.82f, 6.69f, 5.47f}},
    {"Cr", {3.20f, 2.90f, 2.10f}, {3.30f, 3.30f, 3.10f}},
    {"Fe", {2.91f, 2.95f, 2.58f}, {3.09f, 2.93f, 2.77f}},
    {"Ti", {2.10f, 1.79f, 1.33f}, {3.20f, 3.00f, 2.76f}},
    {"Ni", {2.37f, 1.66f, 1.47f}, {4.50f, 3.05f, 2.35f}},
    {"W", {4.37f, 3.30f, 3.00f}, {3.50f, 2.60f, 2.27f}},
    {"Mo", {4.48f, 3.53f, 2.78f}, {4.11f, 3.42f, 3.15f}},
    {"Ir", {3.09f, 2.08f, 1.62f}, {5.59f, 4.07f, 3.27f}},
    {"Rh", {2.59f, 1.86f, 1.55f}, {6.78f, 4.70f, 3.98f}},
    {"Be", {4.19f, 3.19f, 2.78f}, {3.84f, 3.01f, 2.87f}},
    {"TiN", {1.65f, 1.15f, 1.38f}, {3.37f, 1.94f, 1.10f}},
    // Purely imaginary IOR: |r_s| = |r_p| = 1 exactly, i.e. a perfect mirror.
    {"none", {0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}},
}};

}  // namespace

bool conductor_preset(const std::string& name, Rgb* eta, Rgb* k) {
  const std::string suffix = "_palik";
  const std::string base =
      name.size() > suffix.size() && name.ends_with(suffix) ? name.substr(0, name.size() - suffix.size())
                                                            : name;
  for (const auto& preset : kPresets) {
    if (base == preset.name) {
      if (eta) *eta = preset.eta;
      if (k) *k = preset.k;
      return true;
    }
  }
  return false;
}

}  // namespace emlt
