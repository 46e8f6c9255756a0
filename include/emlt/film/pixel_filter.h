#pragma once
// The film's reconstruction filter (Mitsuba's <rfilter>): box, tent, Gaussian,
// Mitchell-Netravali, Catmull-Rom or Lanczos sinc.
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
//
// Negative lobes (Mitchell, Catmull-Rom, Lanczos). Mitsuba adds each sample's value times
// the (possibly negative) filter weight and divides by the sum of the weights, so its pixel
// converges to the integral of footprint times radiance over the integral of the footprint
// inside the image, and may come out negative beside a bright edge. Camera-side samples are
// therefore drawn from the footprint's absolute value and carry a weight, the footprint's
// sign times (integral of |footprint|) / (integral of footprint) over the image; splats
// carry the signed density. Both keep the expectation above.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "emlt/core/math.h"

namespace emlt {

struct PixelFilterDesc {
  enum class Kind { Box, Tent, Gaussian, Mitchell, CatmullRom, Lanczos } kind = Kind::Box;
  float stddev = 0.5f;  // Gaussian: Mitsuba's default; its radius is 4 stddev
  float radius = 1.0f;  // Tent: Mitsuba's default
  // Box: every sample within this many pixels of a pixel centre (on each axis) counts fully
  // for it; Mitsuba's default 0.5 is the pixel itself.
  float box_radius = 0.5f;
  // Mitchell-Netravali's B and C (Mitsuba's defaults); Catmull-Rom is B = 0, C = 1/2.
  // Both reach 2 pixels.
  float b = 1.0f / 3.0f, c = 1.0f / 3.0f;
  int lobes = 3;  // Lanczos: the sinc's lobes, which are also its radius in pixels
};

// A camera-side sample of a pixel: its raster position and the weight its value carries
// (1 unless the filter has negative lobes).
struct FilterSample {
  Vec2 raster;
  float weight = 1.0f;
};

class PixelFilter {
 public:
  PixelFilter(const PixelFilterDesc& desc, int width, int height);

  bool is_box() const { return box_; }
  // Pixels on each side of a pixel's centre that its footprint reaches (0 for the box).
  int reach() const { return reach_; }

  // A raster position for a sample of pixel (x, y), distributed as the footprint's absolute
  // value, and the weight that makes the sample's expectation the footprint's (above).
  FilterSample sample(int x, int y, const Vec2& u) const;

  // Calls add(pixel index, weight) for each pixel whose footprint covers the raster
  // position p, weight = the footprint's density at p (for the box: 1 in p's pixel),
  // negative in a negative lobe.
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
  // The 1D profile's analytic value at offset t (Mitsuba's formula, before tabulation).
  static float profile(const PixelFilterDesc& desc, float t);
  // How far the footprint reaches from a pixel centre, in pixels (Mitsuba's radius).
  static float support_radius(const PixelFilterDesc& desc);

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
      if (wy == 0.0f) continue;
      for (int x = std::max(px - reach_, 0); x <= std::min(px + reach_, width_ - 1); ++x) {
        const float nx = renormalise_edges ? inv_norm_x_[size_t(x)] : inv_total_;
        const float w = wy * density(p.x - (float(x) + 0.5f)) * nx;
        if (w != 0.0f) add(uint32_t(y) * uint32_t(width_) + uint32_t(x), w);
      }
    }
  }

  // Offset t in [lo, hi] (clipped to the support) with density proportional to the
  // profile's absolute value.
  float sample_offset(float lo, float hi, float u) const;
  // Integral from -radius to t of the tabulated profile (signed) or of its absolute value.
  double cdf(const std::vector<double>& cumulative, bool absolute, float t) const;

  bool box_ = true;
  int width_ = 0, height_ = 0, reach_ = 0;
  float radius_ = 0.5f, bin_width_ = 1.0f;
  std::vector<float> bins_;  // profile per bin over [-radius, radius]
  // Integrals up to each bin's start (size bins + 1), of the profile and of its absolute value.
  std::vector<double> cumulative_, cumulative_abs_;
  std::vector<float> inv_norm_x_, inv_norm_y_;  // 1 / footprint integral inside the image
  // Per pixel: integral of |footprint| over integral of footprint, inside the image (1 for
  // a filter without negative lobes).
  std::vector<float> abs_ratio_x_, abs_ratio_y_;
  float inv_total_ = 1.0f;  // 1 / the whole footprint's integral
};

// "box", "tent (radius 1)", ...; describes a filter for messages.
std::string describe(const PixelFilterDesc& desc);

}  // namespace emlt
