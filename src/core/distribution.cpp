#include "emlt/core/distribution.h"

#include <algorithm>

namespace emlt {

Distribution1D::Distribution1D(std::vector<float> weights) : weights_(std::move(weights)) {
  cdf_.resize(weights_.size() + 1);
  cdf_[0] = 0.0;
  for (size_t i = 0; i < weights_.size(); ++i) {
    const float w = std::isfinite(weights_[i]) ? glm::max(weights_[i], 0.0f) : 0.0f;
    weights_[i] = w;
    cdf_[i + 1] = cdf_[i] + w;
  }
  total_ = cdf_.back();
  if (total_ > 0.0) {
    for (double& c : cdf_) c /= total_;
  } else {
    // No mass: callers must check empty_mass(); keep a uniform table so sampling is safe.
    for (size_t i = 0; i < cdf_.size(); ++i) cdf_[i] = double(i) / double(weights_.size());
  }
  if (!cdf_.empty()) cdf_.back() = 1.0;
}

float Distribution1D::pmf(size_t i) const {
  if (i >= weights_.size()) return 0.0f;
  return static_cast<float>(cdf_[i + 1] - cdf_[i]);
}

size_t Distribution1D::sample_discrete(float u, float* pmf_out, float* remapped) const {
  // First bucket whose upper cdf exceeds u; buckets of zero mass are never returned. A
  // short table (a scene's few emitters) is scanned in order, which finds the same bucket
  // as the binary search with fewer branches.
  const double target = double(u);
  size_t i;
  if (weights_.size() <= kLinearScanSize) {
    i = 0;
    while (i + 1 < weights_.size() && !(cdf_[i + 1] > target)) ++i;
  } else {
    const auto it = std::upper_bound(cdf_.begin() + 1, cdf_.end(), target);
    i = std::min<size_t>(size_t(it - cdf_.begin()) - 1, weights_.size() - 1);
  }
  while (i > 0 && cdf_[i + 1] - cdf_[i] <= 0.0) --i;  // guard u on a flat tail
  const double mass = cdf_[i + 1] - cdf_[i];
  if (pmf_out) *pmf_out = static_cast<float>(mass);
  if (remapped) {
    const double r = mass > 0.0 ? (double(u) - cdf_[i]) / mass : 0.0;
    *remapped = glm::clamp(static_cast<float>(r), 0.0f, kOneMinusEpsilon);
  }
  return i;
}

float Distribution1D::sample_continuous(float u, float* pdf_out, size_t* bucket) const {
  float pmf_i = 0.0f, within = 0.0f;
  const size_t i = sample_discrete(u, &pmf_i, &within);
  if (pdf_out) *pdf_out = pmf_i * float(weights_.size());
  if (bucket) *bucket = i;
  const float x = (float(i) + within) / float(weights_.size());
  return glm::min(x, kOneMinusEpsilon);
}

float Distribution1D::pdf(float x) const {
  if (weights_.empty() || !(x >= 0.0f && x < 1.0f)) return 0.0f;
  const size_t i = std::min(size_t(x * float(weights_.size())), weights_.size() - 1);
  return pmf(i) * float(weights_.size());
}

Distribution2D::Distribution2D(const std::vector<float>& weights, size_t width, size_t height)
    : height_(height) {
  rows_.reserve(height);
  std::vector<float> row_mass(height);
  for (size_t y = 0; y < height; ++y) {
    std::vector<float> row(weights.begin() + long(y * width),
                           weights.begin() + long((y + 1) * width));
    rows_.emplace_back(std::move(row));
    row_mass[y] = static_cast<float>(rows_.back().total());
  }
  marginal_ = Distribution1D(std::move(row_mass));
}

Vec2 Distribution2D::sample(const Vec2& u, float* pdf_out) const {
  float pdf_y = 0.0f, pdf_x = 0.0f;
  size_t row = 0;
  const float y = marginal_.sample_continuous(u.y, &pdf_y, &row);
  const float x = rows_[row].sample_continuous(u.x, &pdf_x);
  if (pdf_out) *pdf_out = pdf_x * pdf_y;
  return {x, y};
}

float Distribution2D::pdf(const Vec2& p) const {
  if (!(p.y >= 0.0f && p.y < 1.0f) || !(p.x >= 0.0f && p.x < 1.0f)) return 0.0f;
  const size_t row = std::min(size_t(p.y * float(height_)), height_ - 1);
  return marginal_.pdf(p.y) * rows_[row].pdf(p.x);
}

}  // namespace emlt
