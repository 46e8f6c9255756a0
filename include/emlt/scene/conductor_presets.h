#pragma once
// Named conductors (Mitsuba 0.6 `material` names) as RGB complex indices of refraction.
#include <string>

#include "emlt/core/math.h"

namespace emlt {

// Fills eta + i k for a Mitsuba conductor name: each of the 71 names of Mitsuba 0.6's
// data/ior (Cu, Ag, Au, Al, Cr, W, Mo, Ir, Rh, Be, TiN, Hg, ..., and the "<name>_palik"
// files it has, e.g. Cu_palik, Ni_palik), as the RGB values its RGB build derives (not yet
// divided by extEta); "none" (any case), a perfect mirror (eta = 0, k = 1, reflectance
// exactly 1 at every angle); and emlt's own "Ni", "Fe", "Ti", which Mitsuba lacks.
// Returns false (outputs untouched) for an unknown name.
bool conductor_preset(const std::string& name, Rgb* eta, Rgb* k);

}  // namespace emlt
