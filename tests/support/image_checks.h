#pragma once
// Comparisons of a rendered image with a reference that the estimator tests share.
#include "emlt/image/image.h"

namespace emlt::test {

// The mean over pixels of (r + g + b) / 3.
double grey_mean(const Image& image);

// Largest relative difference of the means of blocks of block x block pixels, each relative
// to the reference block's mean (floored at a quarter of the image mean, so that nearly
// black blocks do not dominate).
double worst_block_error(const Image& reference, const Image& test, int block);

}  // namespace emlt::test
