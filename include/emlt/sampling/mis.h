#pragma once
// Multiple importance sampling weights (Veach 1997, ch. 9). Counts are the number of
// samples each strategy takes; pdfs must be in the same measure.
#include <cmath>

#include "emlt/settings/settings.h"

namespace emlt {

inline float balance_heuristic(float n_this, float pdf_this, float n_other, float pdf_other) {
  const float a = n_this * pdf_this, b = n_other * pdf_other;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

inline float power_heuristic(float n_this, float pdf_this, float n_other, float pdf_other) {
  const float a = n_this * pdf_this, b = n_other * pdf_other;
  // Infinite pdfs (delta strategies) take all the weight.
  if (std::isinf(a * a)) return 1.0f;
  return a * a + b * b > 0.0f ? (a * a) / (a * a + b * b) : 0.0f;
}

// Veach's maximum heuristic (the power heuristic as beta -> infinity): all the weight to the
// strategy with the larger n * pdf. An exact tie is split evenly, so that the two weights
// still sum to one there (a tie given wholly to both sides would count the sample twice).
inline float max_heuristic(float n_this, float pdf_this, float n_other, float pdf_other) {
  const float a = n_this * pdf_this, b = n_other * pdf_other;
  if (!(a > 0.0f) && !(b > 0.0f)) return 0.0f;
  return a > b ? 1.0f : a < b ? 0.0f : 0.5f;
}

// Equal sample counts. SecondOrder weights a fixed pair of samples as Balance does (the
// mixture at alpha = 1/2); its own split lives in the mixture estimator.
inline float mis_weight(MisHeuristic heuristic, float pdf_this, float pdf_other) {
  switch (heuristic) {
    case MisHeuristic::Power: return power_heuristic(1.0f, pdf_this, 1.0f, pdf_other);
    case MisHeuristic::Max: return max_heuristic(1.0f, pdf_this, 1.0f, pdf_other);
    case MisHeuristic::Balance:
    case MisHeuristic::SecondOrder: break;
  }
  return balance_heuristic(1.0f, pdf_this, 1.0f, pdf_other);
}

}  // namespace emlt
