#pragma once
// EMLT's adaptive step scale for the linear kernels (paper §3.4). b_res is the area of the
// bounding box of a set of guide image coordinates divided by the image area; a
// generalised sigmoid w = 1 / (1 + exp(-(b_res - c) / sigma^2)) then interpolates
// alpha = (1 - w) alpha_large + w alpha_small: guides clustered in a small part of the image
// get large steps (to explore), spread-out guides small ones. The paper computes it "based on
// Y"; which set the caller passes (all of Y, or the Upsilon of one path type) is its choice:
// either keeps detailed balance as long as both directions of a move use the same set.
#include <span>

#include "emlt/core/math.h"

namespace emlt::ensemble {

struct AdaptiveAlphaParams {
  double alpha_large = 0.5;   // the paper's alpha_l
  double alpha_small = 0.05;  // alpha_s
  double centre = 0.1;        // c
  double sigma_squared = 0.02;
};

// Fraction of the image covered by the bounding box of the raster positions (0 for fewer
// than two distinct points).
double image_coverage(std::span<const Vec2> raster, int width, int height);

double adaptive_alpha(double coverage, const AdaptiveAlphaParams& params = {});

}  // namespace emlt::ensemble
