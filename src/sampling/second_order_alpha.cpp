#include "emlt/sampling/second_order_alpha.h"

#include <algorithm>
#include <cmath>

namespace emlt {

void SecondOrderAlpha::add(double f, double light_pdf, double bsdf_pdf) {
  const double mean = 0.5 * (light_pdf + bsdf_pdf);
  if (!(mean > 0.0) || !std::isfinite(mean) || !(f != 0.0) || !std::isfinite(f)) return;
  const double ratio = f / mean;
  // dp / pbar lies in [-1, 1]: the terms stay finite whatever the densities' scale.
  const double share = 0.5 * (light_pdf - bsdf_pdf) / mean;
  first_ += ratio * ratio * share;
  second_ += ratio * ratio * share * share;
}

void SecondOrderAlpha::merge(const SecondOrderAlpha& other) {
  first_ += other.first_;
  second_ += other.second_;
}

double SecondOrderAlpha::unclamped() const {
  if (!(second_ > 0.0) || !std::isfinite(first_ / second_)) return 0.5;
  return 0.25 * (2.0 + first_ / second_);  // Eq. 5.4
}

double SecondOrderAlpha::alpha(double clamp) const {
  const double c = std::clamp(clamp, 0.0, 0.5);
  return std::clamp(unclamped(), c, 1.0 - c);
}

}  // namespace emlt
