#pragma once
// Whether a reconstruction filter has negative lobes (Mitchell-Netravali, Catmull-Rom and
// Lanczos mostly do): a pixel's splat sums may then be negative beside a bright edge, and the
// checks of a saved film must accept them. Kept apart from pixel_filter.h, which nearly every
// file includes, for the few that ask.
#include "emlt/film/pixel_filter.h"

namespace emlt {

bool has_negative_lobes(const PixelFilterDesc& desc);

}  // namespace emlt
