#include "emlt/film/pixel_filter.h"

#include <algorithm>
#include <cmath>

namespace emlt {

namespace {

// The profile is tabulated as Mitsuba 0.6 evaluates it: 31 steps over [0, radius], each
// step holding the profile's value at the step's inner end (so the effective filter is a
// little wider than the analytic one). Mirrored, that is 62 bins over [-radius, radius].
constexpr int kStepsPerSide = 31;
constexpr int kBins = 2 * kStepsPerSide;

float profile(const PixelFilterDesc& desc, float radius, float t) {
  switch (desc.kind) {
    case PixelFilterDesc::Kind::Tent:
      return std::max(0.0f, 1.0f - std::abs(t) / radius);
    case PixelFilterDesc::Kind::Gaussian: {
      // Mitsuba's windowed Gaussian: the tail at the radius is subtracted so that the
      // profile falls to zero there.
      const float alpha = -1.0f / (2.0f * desc.stddev * desc.stddev);
      return std::max(0.0f, std::exp(alpha * t * t) - std::exp(alpha * radius * radius));
    }
    case PixelFilterDesc::Kind::Box:
      break;
  }
  return std::abs(t) <= radius ? 1.0f : 0.0f;
}

}  // namespace

PixelFilter::PixelFilter(const PixelFilterDesc& desc, int width, int height)
    : box_(desc.kind == PixelFilterDesc::Kind::Box), width_(width), height_(height) {
  if (box_) return;
  radius_ = desc.kind == PixelFilterDesc::Kind::Gaussian ? 4.0f * desc.stddev : desc.radius;
  reach_ = int(std::ceil(radius_ + 0.5f)) - 1;
  bin_width_ = 2.0f * radius_ / float(kBins);
  bins_.resize(kBins);
  cumulative_.assign(kBins + 1, 0.0);
  for (int i = 0; i < kBins; ++i) {
    const int step = i < kStepsPerSide ? kStepsPerSide - 1 - i : i - kStepsPerSide;
    bins_[size_t(i)] = profile(desc, radius_, float(step) * bin_width_);
    cumulative_[size_t(i) + 1] = cumulative_[size_t(i)] + double(bins_[size_t(i)]) * bin_width_;
  }
  const auto inverse_norms = [&](int size) {
    std::vector<float> inv(static_cast<size_t>(size));
    for (int i = 0; i < size; ++i) {
      const float centre = float(i) + 0.5f;
      const double inside = cdf(float(size) - centre) - cdf(-centre);
      inv[size_t(i)] = inside > 0.0 ? float(1.0 / inside) : 0.0f;
    }
    return inv;
  };
  inv_total_ = float(1.0 / cumulative_.back());
  inv_norm_x_ = inverse_norms(width);
  inv_norm_y_ = inverse_norms(height);
}

float PixelFilter::density(float t) const {
  if (box_) return std::abs(t) <= 0.5f ? 1.0f : 0.0f;
  if (!(std::abs(t) < radius_)) return 0.0f;
  const int bin = std::min(int((t + radius_) / bin_width_), kBins - 1);
  return bins_[size_t(std::max(bin, 0))];
}

double PixelFilter::cdf(float t) const {
  if (t <= -radius_) return 0.0;
  if (t >= radius_) return cumulative_.back();
  const int bin = std::min(int((t + radius_) / bin_width_), kBins - 1);
  const float start = -radius_ + float(bin) * bin_width_;
  return cumulative_[size_t(bin)] + double(bins_[size_t(bin)]) * double(t - start);
}

float PixelFilter::sample_offset(float lo, float hi, float u) const {
  lo = std::max(lo, -radius_);
  hi = std::min(hi, radius_);
  const double a = cdf(lo), b = cdf(hi);
  const double target = a + double(u) * (b - a);
  // The first bin whose end passes the target; empty bins are never chosen.
  const auto it = std::upper_bound(cumulative_.begin() + 1, cumulative_.end(), target);
  const int bin = std::min(int(it - cumulative_.begin()) - 1, kBins - 1);
  const float start = -radius_ + float(bin) * bin_width_;
  const float value = bins_[size_t(bin)];
  const float t =
      value > 0.0f ? start + float((target - cumulative_[size_t(bin)]) / double(value)) : start;
  return std::clamp(t, lo, hi);
}

Vec2 PixelFilter::sample(int x, int y, const Vec2& u) const {
  if (box_) return Vec2(float(x), float(y)) + u;
  const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
  return {cx + sample_offset(-cx, float(width_) - cx, u.x),
          cy + sample_offset(-cy, float(height_) - cy, u.y)};
}

std::string describe(const PixelFilterDesc& desc) {
  switch (desc.kind) {
    case PixelFilterDesc::Kind::Tent:
      return "tent (radius " + std::to_string(desc.radius) + ")";
    case PixelFilterDesc::Kind::Gaussian:
      return "gaussian (stddev " + std::to_string(desc.stddev) + ")";
    case PixelFilterDesc::Kind::Box:
      break;
  }
  return "box";
}

}  // namespace emlt
