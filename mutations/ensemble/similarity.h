#pragma once
// Path similarity of Ensemble MLT (Bashford-Rogers et al. 2021, section 3.1.2, eqs. 8-9) and
// the similarity-weighted choice of one guide path from the subset Upsilon of the
// complementary ensemble.
//
//   d(x, v) = max(|x - v|^2 / l^2, eps)^-1,   eps = 1e-4
//   S(x, v) = 2 / (1 + e^-d) - 1             (eq. 8)  which is exactly tanh(d / 2)
//   S(x, v, j, k) = prod_{l=j..k} S(x_l, v_l) (eq. 9)
//
// l is an optional length scale (design notes section 3: S depends on the scene's units;
// l = 1 is the paper's literal form). We evaluate tanh(d/2) rather than 2/(1+e^-d) - 1
// because the latter loses every digit for small d (far vertices, S ~ d/2), and we work
// with log S so that products over many vertices neither underflow nor lose precision.
//
// Guide selection. A strategy that picks one guide v^n with P(n | x) proportional to a
// weight (e.g. S(x, v^n)) is a mixture of kernels whose mixture weights depend on the state.
// Detailed balance holds component by component only if the acceptance ratio contains
// P(n | y) / P(n | x), with P(n | y) computed from the proposed state's own weights against
// the same Upsilon (design notes section 3). `guide_log_probability` provides both factors.
#include <cstddef>
#include <cstdint>
#include <span>

#include "emlt/core/math.h"
#include "emlt/core/rng.h"

namespace emlt::ensemble {

inline constexpr double kPaperSimilarityEpsilon = 1e-4;

struct SimilarityParams {
  double epsilon = kPaperSimilarityEpsilon;  // floor on the (scaled) squared distance
  double length_scale = 1.0;                 // distances are divided by it; 1 = paper literal
};

// log S for two vertices a squared distance apart (eq. 8). Always <= 0; -inf only when
// the squared distance is infinite.
double log_similarity_from_squared_distance(double squared_distance,
                                            const SimilarityParams& params);

inline double similarity_from_squared_distance(double squared_distance,
                                               const SimilarityParams& params) {
  return std::exp(log_similarity_from_squared_distance(squared_distance, params));
}

double log_vertex_similarity(const Vec3& a, const Vec3& b, const SimilarityParams& params);
double log_vertex_similarity(const Vec2& a, const Vec2& b, const SimilarityParams& params);
inline double vertex_similarity(const Vec3& a, const Vec3& b, const SimilarityParams& params) {
  return std::exp(log_vertex_similarity(a, b, params));
}

// log of eq. 9: sum over corresponding vertices of the two spans (same length required).
double log_path_similarity(std::span<const Vec3> path_vertices,
                           std::span<const Vec3> guide_vertices, const SimilarityParams& params);

// out[n] = log S(point, guides[n]) for every guide (out.size() == guides.size()).
void log_similarities_to_guides(const Vec3& point, std::span<const Vec3> guides,
                                const SimilarityParams& params, std::span<double> out);
void log_similarities_to_guides(const Vec2& point, std::span<const Vec2> guides,
                                const SimilarityParams& params, std::span<double> out);

// Normalises unnormalised log weights into probabilities (softmax, shifted by the maximum
// so that very small similarities do not underflow). When no weight is positive and finite
// the distribution is uniform: a deterministic rule of the weights alone, so that the same
// rule applies when the reverse move evaluates P(n | y). Returns the Kish effective number
// of guides, (sum w)^2 / sum w^2, of the normalised weights.
double normalise_log_weights(std::span<const double> log_weights, std::span<double> probabilities);

// log P(index | state) for the weights of that state.
double guide_log_probability(std::span<const double> log_weights, size_t index);

struct GuideChoice {
  uint32_t index = 0;
  double log_probability = 0.0;  // log P(index | current state)
};

// Draws one guide with probability proportional to exp(log_weights[n]). Requires at least
// one weight.
GuideChoice choose_guide(std::span<const double> log_weights, Rng& rng);

}  // namespace emlt::ensemble
