#include "emlt/film/pixel_filter.h"

#include <algorithm>
#include <cmath>

#include "emlt/film/filter_lobes.h"

namespace emlt {

namespace {

// The profile is tabulated as Mitsuba 0.6 evaluates it: 31 steps over [0, radius], each
// step holding the profile's value at the step's inner end (so the effective filter is a
// little wider than the analytic one). Mirrored, that is 62 bins over [-radius, radius].
constexpr int kStepsPerSide = 31;
constexpr int kBins = 2 * kStepsPerSide;

// Mitchell and Netravali's cubic with parameters B and C (zero beyond 2 pixels).
float mitchell_netravali(float b, float c, float t) {
  const float x = std::abs(t), x2 = x * x, x3 = x2 * x;
  if (x < 1.0f)
    return ((12.0f - 9.0f * b - 6.0f * c) * x3 + (-18.0f + 12.0f * b + 6.0f * c) * x2 +
            (6.0f - 2.0f * b)) /
           6.0f;
  if (x < 2.0f)
    return ((-b - 6.0f * c) * x3 + (6.0f * b + 30.0f * c) * x2 + (-12.0f * b - 48.0f * c) * x +
            (8.0f * b + 24.0f * c)) /
           6.0f;
  return 0.0f;
}

// The sinc windowed by a sinc `lobes` times as wide. Near 0 it is 1, taken as Mitsuba
// takes it below its single-precision epsilon.
float lanczos(int lobes, float t) {
  const float x = std::abs(t), radius = float(lobes);
  if (x < 1e-4f) return 1.0f;
  if (x > radius) return 0.0f;
  const float a = kPi * x, b = a / radius;
  return std::sin(a) * std::sin(b) / (a * b);
}

}  // namespace

float PixelFilter::support_radius(const PixelFilterDesc& desc) {
  switch (desc.kind) {
    case PixelFilterDesc::Kind::Gaussian:
      return 4.0f * desc.stddev;
    case PixelFilterDesc::Kind::Mitchell:
    case PixelFilterDesc::Kind::CatmullRom:
      return 2.0f;
    case PixelFilterDesc::Kind::Lanczos:
      return float(desc.lobes);
    case PixelFilterDesc::Kind::Tent:
      return desc.radius;
    case PixelFilterDesc::Kind::Box:
      break;
  }
  return desc.box_radius;
}

float PixelFilter::profile(const PixelFilterDesc& desc, float t) {
  const float radius = support_radius(desc);
  switch (desc.kind) {
    case PixelFilterDesc::Kind::Tent:
      return std::max(0.0f, 1.0f - std::abs(t) / radius);
    case PixelFilterDesc::Kind::Gaussian: {
      // Mitsuba's windowed Gaussian: the tail at the radius is subtracted so that the
      // profile falls to zero there.
      const float alpha = -1.0f / (2.0f * desc.stddev * desc.stddev);
      return std::max(0.0f, std::exp(alpha * t * t) - std::exp(alpha * radius * radius));
    }
    case PixelFilterDesc::Kind::Mitchell:
      return mitchell_netravali(desc.b, desc.c, t);
    case PixelFilterDesc::Kind::CatmullRom:
      return mitchell_netravali(0.0f, 0.5f, t);
    case PixelFilterDesc::Kind::Lanczos:
      return lanczos(desc.lobes, t);
    case PixelFilterDesc::Kind::Box:
      break;
  }
  return std::abs(t) <= radius ? 1.0f : 0.0f;
}

PixelFilter::PixelFilter(const PixelFilterDesc& desc, int width, int height)
    : box_(desc.kind == PixelFilterDesc::Kind::Box && desc.box_radius == 0.5f),
      width_(width),
      height_(height) {
  if (box_) return;
  radius_ = support_radius(desc);
  reach_ = int(std::ceil(radius_ + 0.5f)) - 1;
  bin_width_ = 2.0f * radius_ / float(kBins);
  bins_.resize(kBins);
  cumulative_.assign(kBins + 1, 0.0);
  cumulative_abs_.assign(kBins + 1, 0.0);
  for (int i = 0; i < kBins; ++i) {
    const int step = i < kStepsPerSide ? kStepsPerSide - 1 - i : i - kStepsPerSide;
    // Mitsuba evaluates step k at radius * k / 31 (in single precision).
    const float value = profile(desc, radius_ * float(step) / float(kStepsPerSide));
    bins_[size_t(i)] = value;
    cumulative_[size_t(i) + 1] = cumulative_[size_t(i)] + double(value) * bin_width_;
    cumulative_abs_[size_t(i) + 1] =
        cumulative_abs_[size_t(i)] + double(std::abs(value)) * bin_width_;
  }
  // Per pixel of a row or column: 1 / the footprint's integral inside the image, and the
  // integral of its absolute value over that. A footprint whose integral inside the image
  // is not positive (no filter Mitsuba has: their central lobe dominates) gets no light.
  const auto norms = [&](int size, std::vector<float>& inv, std::vector<float>& ratio) {
    inv.assign(size_t(size), 0.0f);
    ratio.assign(size_t(size), 0.0f);
    for (int i = 0; i < size; ++i) {
      const float centre = float(i) + 0.5f;
      const double inside =
          cdf(cumulative_, false, float(size) - centre) - cdf(cumulative_, false, -centre);
      const double inside_abs =
          cdf(cumulative_abs_, true, float(size) - centre) - cdf(cumulative_abs_, true, -centre);
      if (!(inside > 0.0)) continue;
      inv[size_t(i)] = float(1.0 / inside);
      ratio[size_t(i)] = float(inside_abs / inside);
    }
  };
  inv_total_ = float(1.0 / cumulative_.back());
  norms(width, inv_norm_x_, abs_ratio_x_);
  norms(height, inv_norm_y_, abs_ratio_y_);
}

float PixelFilter::density(float t) const {
  if (box_) return std::abs(t) <= 0.5f ? 1.0f : 0.0f;
  if (!(std::abs(t) < radius_)) return 0.0f;
  const int bin = std::min(int((t + radius_) / bin_width_), kBins - 1);
  return bins_[size_t(std::max(bin, 0))];
}

double PixelFilter::cdf(const std::vector<double>& cumulative, bool absolute, float t) const {
  if (t <= -radius_) return 0.0;
  if (t >= radius_) return cumulative.back();
  const int bin = std::min(int((t + radius_) / bin_width_), kBins - 1);
  const float start = -radius_ + float(bin) * bin_width_;
  const float value = absolute ? std::abs(bins_[size_t(bin)]) : bins_[size_t(bin)];
  return cumulative[size_t(bin)] + double(value) * double(t - start);
}

float PixelFilter::sample_offset(float lo, float hi, float u) const {
  lo = std::max(lo, -radius_);
  hi = std::min(hi, radius_);
  const double a = cdf(cumulative_abs_, true, lo), b = cdf(cumulative_abs_, true, hi);
  const double target = a + double(u) * (b - a);
  // The first bin whose end passes the target; empty bins are never chosen.
  const auto it = std::upper_bound(cumulative_abs_.begin() + 1, cumulative_abs_.end(), target);
  const int bin = std::min(int(it - cumulative_abs_.begin()) - 1, kBins - 1);
  const float start = -radius_ + float(bin) * bin_width_;
  const float value = std::abs(bins_[size_t(bin)]);
  const float t =
      value > 0.0f ? start + float((target - cumulative_abs_[size_t(bin)]) / double(value)) : start;
  return std::clamp(t, lo, hi);
}

FilterSample PixelFilter::sample(int x, int y, const Vec2& u) const {
  if (box_) return {Vec2(float(x), float(y)) + u, 1.0f};
  const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
  const float tx = sample_offset(-cx, float(width_) - cx, u.x);
  const float ty = sample_offset(-cy, float(height_) - cy, u.y);
  // The sign of the footprint where the sample fell, times |integral| / integral per axis.
  const float sx = density(tx) < 0.0f ? -1.0f : 1.0f;
  const float sy = density(ty) < 0.0f ? -1.0f : 1.0f;
  return {Vec2(cx + tx, cy + ty), sx * sy * abs_ratio_x_[size_t(x)] * abs_ratio_y_[size_t(y)]};
}

bool has_negative_lobes(const PixelFilterDesc& desc) {
  // The table's steps (as the constructor evaluates them) are what a splat can carry.
  const float radius = PixelFilter::support_radius(desc);
  for (int step = 0; step < kStepsPerSide; ++step)
    if (PixelFilter::profile(desc, radius * float(step) / float(kStepsPerSide)) < 0.0f) return true;
  return false;
}

std::string describe(const PixelFilterDesc& desc) {
  switch (desc.kind) {
    case PixelFilterDesc::Kind::Tent:
      return "tent (radius " + std::to_string(desc.radius) + ")";
    case PixelFilterDesc::Kind::Gaussian:
      return "gaussian (stddev " + std::to_string(desc.stddev) + ")";
    case PixelFilterDesc::Kind::Mitchell:
      return "mitchell (B " + std::to_string(desc.b) + ", C " + std::to_string(desc.c) + ")";
    case PixelFilterDesc::Kind::CatmullRom:
      return "catmullrom";
    case PixelFilterDesc::Kind::Lanczos:
      return "lanczos (lobes " + std::to_string(desc.lobes) + ")";
    case PixelFilterDesc::Kind::Box:
      break;
  }
  return desc.box_radius == 0.5f ? "box" : "box (radius " + std::to_string(desc.box_radius) + ")";
}

}  // namespace emlt
