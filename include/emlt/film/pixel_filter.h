#pragma once
// The film's reconstruction filter (Mitsuba's <rfilter>): box, tent or Gaussian.
//
// A pixel's value is the image plane's radiance integrated against the pixel's footprint,
// the filter centred on the pixel and normalised over the part of it inside the image.
// Nothing is weighted after the fact, so that both kinds of estimator keep their
// expectation:
//  - camera-side estimators (pt, direct, bdpt's camera paths) draw each sample's raster
//    position from the pixel's footprint (filter importance sampling);
//  - light-side estimators (bdpt's light tracing, the MCMC chains) add each contribution
//    to every pixel whose footprint covers its raster position, with that footprint's
//    density there.
// Both converge to Mitsuba's image, whose pixels are filter-weighted averages of samples
// drawn uniformly over the image. The particle tracer alone splats without the edge
// renormalisation (splat_unrenormalised), as Mitsuba's particle tracer does.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "emlt/core/math.h"

namespace emlt {

struct PixelFilterDesc {
  enum class Kind { Box, Tent, Gaussian } kind = Kind::Box;
  float stddev = 0.5f;  // Gaussian: Mitsuba's default; its radius is 4 stddev
  float radius = 1.0f;  // Tent: Mitsuba's default
};

class PixelFilter {
 public:
  PixelFilter(const PixelFilterDesc& desc, int width, int height);

  bool is_box() const { return box_; }
  // Pixels on each side of a pixel's centre that its footprint reaches (0 for the box).
  int reach() const { return reach_; }

  // A raster position for a sample of pixel (x, y), distributed as its footprint.
  Vec2 sample(int x, int y, const Vec2& u) const;

  // Calls add(pixel index, weight) for each pixel whose footprint covers the raster
  // position p, weight = the footprint's density at p (for the box: 1 in p's pixel).
  template <class Add>
  void splat(const Vec2& p, Add&& add) const {
    splat_with(p, add, true);
  }

  // As splat, but with every footprint normalised over its whole support, as Mitsuba's
  // particle tracer splats (its image has no per-pixel weight to divide by): a pixel near
  // the image's edge loses the part of its footprint that lies off the image and comes out
  // darker than the camera-side estimators' pixel. The same as splat for the box filter.
  template <class Add>
  void splat_unrenormalised(const Vec2& p, Add&& add) const {
    splat_with(p, add, false);
  }

  // The 1D profile's tabulated density at offset t from a pixel centre (unnormalised).
  float density(float t) const;

 private:
  template <class Add>
  void splat_with(const Vec2& p, Add& add, bool renormalise_edges) const {
    if (!(p.x >= 0.0f && p.y >= 0.0f && p.x < float(width_) && p.y < float(height_))) return;
    const int px = int(p.x), py = int(p.y);
    if (box_) {
      add(uint32_t(py) * uint32_t(width_) + uint32_t(px), 1.0f);
      return;
    }
    for (int y = std::max(py - reach_, 0); y <= std::min(py + reach_, height_ - 1); ++y) {
      const float ny = renormalise_edges ? inv_norm_y_[size_t(y)] : inv_total_;
      const float wy = density(p.y - (float(y) + 0.5f)) * ny;
      if (!(wy > 0.0f)) continue;
      for (int x = std::max(px - reach_, 0); x <= std::min(px + reach_, width_ - 1); ++x) {
        const float nx = renormalise_edges ? inv_norm_x_[size_t(x)] : inv_total_;
        const float w = wy * density(p.x - (float(x) + 0.5f)) * nx;
        if (w > 0.0f) add(uint32_t(y) * uint32_t(width_) + uint32_t(x), w);
      }
    }
  }

  // Offset t in [lo, hi] (clipped to the support) with density proportional to the profile.
  float sample_offset(float lo, float hi, float u) const;
  // Integral of the tabulated profile from -radius to t.
  double cdf(float t) const;

  bool box_ = true;
  int width_ = 0, height_ = 0, reach_ = 0;
  float radius_ = 0.5f, bin_width_ = 1.0f;
  std::vector<float> bins_;                     // profile per bin over [-radius, radius]
  std::vector<double> cumulative_;              // integral up to each bin's start, size bins + 1
  std::vector<float> inv_norm_x_, inv_norm_y_;  // 1 / footprint integral inside the image
  float inv_total_ = 1.0f;                      // 1 / the whole footprint's integral
};

// "box", "tent", "gaussian"; describes a filter for messages.
std::string describe(const PixelFilterDesc& desc);

}  // namespace emlt
