#pragma once
// Multiple importance sampling weights (Veach 1997, ch. 9). Counts are the number of
// samples each strategy takes; pdfs must be in the same measure.
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

inline float mis_weight(MisHeuristic heuristic, float pdf_this, float pdf_other) {
  return heuristic == MisHeuristic::Balance ? balance_heuristic(1.0f, pdf_this, 1.0f, pdf_other)
                                            : power_heuristic(1.0f, pdf_this, 1.0f, pdf_other);
}

}  // namespace emlt
