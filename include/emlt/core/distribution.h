#pragma once
// Piecewise-constant distributions over [0,1) and [0,1)^2, built from non-negative
// weights. Their pdfs are exact for the samplers (no interpolation mismatch), which MIS
// and Metropolis acceptance ratios rely on.
#include <cstddef>
#include <vector>

#include "emlt/core/math.h"

namespace emlt {

class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(std::vector<float> weights);

  size_t size() const { return weights_.size(); }
  double total() const { return total_; }
  bool empty_mass() const { return total_ <= 0.0; }

  // Discrete use: index i with probability pmf(i). `remapped` (optional) receives u
  // rescaled to [0,1) inside the chosen bucket, so one number can drive two decisions.
  size_t sample_discrete(float u, float* pmf = nullptr, float* remapped = nullptr) const;
  float pmf(size_t i) const;

  // Continuous use: x in [0,1) with density pdf(x) = size() * pmf(bucket of x).
  float sample_continuous(float u, float* pdf = nullptr, size_t* bucket = nullptr) const;
  float pdf(float x) const;

 private:
  static constexpr size_t kLinearScanSize = 16;
  std::vector<float> weights_;
  std::vector<double> cdf_;  // size()+1 entries, cdf_[0] = 0, cdf_.back() = 1
  double total_ = 0.0;
};

// 2-D piecewise-constant density on [0,1)^2 over a width x height grid: a marginal over
// rows (y) and one conditional per row (x).
class Distribution2D {
 public:
  Distribution2D() = default;
  // weights are row-major, width * height entries.
  Distribution2D(const std::vector<float>& weights, size_t width, size_t height);

  bool empty_mass() const { return marginal_.empty_mass(); }
  Vec2 sample(const Vec2& u, float* pdf = nullptr) const;  // density w.r.t. area on [0,1)^2
  float pdf(const Vec2& p) const;

 private:
  size_t height_ = 0;  // a row's width is its conditional's size()
  std::vector<Distribution1D> rows_;
  Distribution1D marginal_;
};

}  // namespace emlt
