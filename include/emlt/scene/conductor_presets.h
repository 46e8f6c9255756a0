#pragma once
// Named conductors (Mitsuba 0.6 `material` names) as RGB complex indices of refraction.
#include <string>

#include "emlt/core/math.h"

namespace emlt {

// Fills eta + i k for a Mitsuba conductor name: "Cu", "Ag", "Au", "Al", "Cr", "Fe", "Ni",
// "Ti", "W", "Mo", "Ir", "Rh", "Be", "TiN", "none" (and "<name>_palik" for each).
// "none" is a perfect mirror (eta = 0, k = 1, reflectance exactly 1 at every angle).
// Returns false (outputs untouched) for an unknown name.
bool conductor_preset(const std::string& name, Rgb* eta, Rgb* k);

}  // namespace emlt
