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
// because the latter loses every digit for small d (far vertices, S ~ d/2), and keep
// products over many vertices as SimilarityProducts (or logs), which neither underflow nor
// lose precision.
//
// Guide selection. A strategy that picks one guide v^n with P(n | x) proportional to a
// weight (e.g. S(x, v^n)) is a mixture of kernels whose mixture weights depend on the state.
// Detailed balance holds component by component only if the acceptance ratio contains
// P(n | y) / P(n | x), with P(n | y) computed from the proposed state's own weights against
// the same Upsilon (design notes section 3). `guide_log_probability` provides both factors.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <span>
#include <type_traits>
#include <vector>

#include "emlt/core/math.h"
#include "emlt/core/rng.h"

namespace emlt::ensemble {

inline constexpr double kPaperSimilarityEpsilon = 1e-4;

// Scratch space with one entry per guide, on the stack up to kStackGuides (the CLI caps M
// at 64): a heap allocation per guided step cost as much as the step's arithmetic.
inline constexpr size_t kStackGuides = 64;

// Only the `size` entries in use are constructed (default-initialised: arithmetic types are
// left as they are): constructing all kStackGuides SimilarityProducts cost 130 stores a
// buffer, more than filling the 8 a step uses.
template <class T>
class GuideBuffer {
  static_assert(std::is_trivially_destructible_v<T>);

 public:
  // The entries live on the stack, or (more than kStackGuides) in heap_; data_ points to them
  // either way, so that reading a buffer is one load (a std::vector member and a test a read
  // cost a guided step a few percent; docs/experiments.md, "Cost per mutation").
  explicit GuideBuffer(size_t size) : size_(size) {
    if (size > kStackGuides) {
      heap_ = std::make_unique<T[]>(size);
      data_ = heap_.get();
    } else {
      data_ = std::launder(reinterpret_cast<T*>(stack_));
      std::uninitialized_default_construct_n(data_, size);
    }
  }
  GuideBuffer(const GuideBuffer&) = delete;
  GuideBuffer& operator=(const GuideBuffer&) = delete;

  std::span<T> span() { return {data_, size_}; }
  std::span<const T> span() const { return {data_, size_}; }
  T& operator[](size_t n) { return data_[n]; }
  size_t size() const { return size_; }

 private:
  alignas(T) std::byte stack_[kStackGuides * sizeof(T)];
  std::unique_ptr<T[]> heap_;
  T* data_;
  size_t size_;
};

struct SimilarityParams {
  double epsilon = kPaperSimilarityEpsilon;  // floor on the (scaled) squared distance
  double length_scale = 1.0;                 // distances are divided by it; 1 = paper literal
};

// S for two vertices a squared distance apart (eq. 8), in [0, 1]: tanh(d / 2) to single
// precision (within 3e-7 relative), evaluated in float from f = max(|x - v|^2 / l^2, eps)
// = 1 / d rounded to float. Single precision is ample for a weight (the acceptance ratios
// need the same function of the state in both directions, not a precise one), and a row of
// guides then takes four lanes a vector operation instead of two: the double-precision
// form, tanh to double rounding, cost 85 instructions a guide, most of EMLT's similarity
// time (docs/experiments.md, "Cost per mutation"). The distance itself is
// computed in double, as before.
inline double floored_scaled_distance(double squared_distance, const SimilarityParams& params) {
  const double length_squared = params.length_scale * params.length_scale;
  const double scaled =
      length_squared == 1.0 ? squared_distance : squared_distance / length_squared;
  return std::max(scaled, params.epsilon);
}
// Three ranges of f, y = d / 2 = 1 / (2 f):
// f < kNearSimilarity: y > 9.1, where tanh(y) rounds to 1 in float (it does from 9.01 on).
inline constexpr float kNearSimilarity = 0.0549f;
// f > kFarSimilarity: y < 1/16, where the series below is exact to float rounding.
inline constexpr float kFarSimilarity = 8.0f;
// tanh(y) = y (1 - y^2/3 + 2y^4/15 - 17y^6/315 + ...); the first omitted term is below
// 4e-9 relative for y <= 1/16.
inline float far_similarity(float floored) {
  const float half_d = 0.5f * (1.0f / floored);
  const float y2 = half_d * half_d;
  return half_d * (1.0f + y2 * (-1.0f / 3.0f + y2 * (2.0f / 15.0f)));
}
// The middle range, y in [1/16, 9.1]: tanh(y) = -t / (t + 2) with t = expm1(-2y).
// -2y = k ln 2 + r with |r| <= ln 2 / 2 (Cody-Waite: ln 2's high part has 9 significant
// bits, so k ln2_high is exact for the |k| <= 27 here), expm1(r) by its Taylor series to
// r^7 / 7! (the rest is below 2e-8 of r), then expm1(-2y) = 2^k expm1(r) + (2^k - 1). No
// branch and no library call, so that rows of guides vectorise.
inline float middle_similarity(float floored) {
  const float x = -1.0f / floored;  // -2y
  constexpr float kInverseLn2 = 1.44269504f;
  constexpr float kLn2High = 0.693359375f;
  constexpr float kLn2Low = -2.12194440e-4f;
  constexpr float kRoundShift = 0x1.8p23f;  // adding and subtracting it rounds to an integer
  const float shifted = x * kInverseLn2 + kRoundShift;
  const float k = shifted - kRoundShift;
  const float r = (x - k * kLn2High) - k * kLn2Low;
  const float q =
      1.0f / 2 +
      r * (1.0f / 6 + r * (1.0f / 24 + r * (1.0f / 120 + r * (1.0f / 720 + r * (1.0f / 5040)))));
  const float expm1_r = r + r * r * q;
  // 2^k, k in [-27, 0]: k is also the difference of the bit patterns of `shifted` and
  // kRoundShift (one unit in the last place of both is 1), integer arithmetic that
  // vectorises where a conversion of k to an integer would not.
  const uint32_t k_bits = std::bit_cast<uint32_t>(shifted) - std::bit_cast<uint32_t>(kRoundShift);
  const float power = std::bit_cast<float>((k_bits + 127) << 23);
  const float t = power * expm1_r + (power - 1.0f);
  return -t / (t + 2.0f);
}
inline double similarity_from_floored(double floored) {
  const float f = float(floored);
  if (f < kNearSimilarity) return 1.0;
  if (f > kFarSimilarity) return double(far_similarity(f));
  return double(middle_similarity(f));
}
inline double similarity_from_squared_distance(double squared_distance,
                                               const SimilarityParams& params) {
  return similarity_from_floored(floored_scaled_distance(squared_distance, params));
}

// log S (eq. 8). Always <= 0; -inf only when the squared distance is infinite.
inline double log_similarity_from_squared_distance(double squared_distance,
                                                   const SimilarityParams& params) {
  return std::log(similarity_from_squared_distance(squared_distance, params));
}

inline double vertex_similarity(const Vec3& a, const Vec3& b, const SimilarityParams& params) {
  const DVec3 offset = DVec3(a) - DVec3(b);
  return similarity_from_squared_distance(glm::dot(offset, offset), params);
}

double log_vertex_similarity(const Vec3& a, const Vec3& b, const SimilarityParams& params);
double log_vertex_similarity(const Vec2& a, const Vec2& b, const SimilarityParams& params);

// A product of similarities (eq. 9) kept as product * exp(log_part): one log per product
// instead of one per factor, without underflow however many small factors it has.
class SimilarityProduct {
 public:
  void multiply(double similarity) {
    if (similarity < kRenormalise) {
      log_part_ += std::log(similarity);  // 0 gives -inf; NaN passes on to the product
      return;
    }
    product_ *= similarity;
    if (product_ < kRenormalise) {
      log_part_ += std::log(product_);
      product_ = 1.0;
    }
  }
  // A factor given as its log (a weight kept in log space elsewhere).
  void multiply_log(double log_factor) { log_part_ += log_factor; }
  // The product itself when no factor needed the log part (NaN stays NaN).
  bool is_plain() const { return log_part_ == 0.0; }
  double plain() const { return product_; }
  double log() const { return log_part_ + std::log(product_); }

  // Both factors >= kRenormalise keeps the product a normal double.
  static constexpr double kRenormalise = 1e-150;

 private:
  double product_ = 1.0;
  double log_part_ = 0.0;
};

// log of eq. 9: sum over corresponding vertices of the two spans (same length required).
double log_path_similarity(std::span<const Vec3> path_vertices,
                           std::span<const Vec3> guide_vertices, const SimilarityParams& params);

// out[n] = S(point, v_n) = vertex_similarity(point, v_n) for guide points given as
// coordinate arrays, v_n = (x[n], y[n], z[n]) (the float positions, converted): the layout
// in which the common case vectorises.
void similarities_to_guides(const Vec3& point, std::span<const double> x, std::span<const double> y,
                            std::span<const double> z, const SimilarityParams& params,
                            std::span<double> out);

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

// normalise_log_weights for weights given as similarity products (weight n =
// exp(weights[n].log())): the same rule, without a log and an exp per weight when every
// weight is a plain positive double. `usable` is false when no weight is positive and
// finite (then the probabilities are uniform).
struct NormalisedWeights {
  double effective_guides = 0.0;
  bool usable = false;
};
NormalisedWeights normalise_weights(std::span<const SimilarityProduct> weights,
                                    std::span<double> probabilities);

// normalise_weights for the weights first[n] * second[n] of two rows of similarities (second
// empty: first[n] alone), formed as SimilarityProduct{}.multiply(first[n]), then
// .multiply(second[n]): the same probabilities and effective count, bit for bit. When every
// weight is a plain positive double (no factor or product below kRenormalise, no NaN) the
// products are never built: they were a third of an anisotropic fit's cost
// (docs/experiments.md, "Cost per mutation").
NormalisedWeights normalise_row_products(std::span<const double> first,
                                         std::span<const double> second,
                                         std::span<double> probabilities);

// log P(index | state) for the weights of that state.
double guide_log_probability(std::span<const double> log_weights, size_t index);

struct GuideChoice {
  uint32_t index = 0;
  double log_probability = 0.0;  // log P(index | current state)
};

// Draws one guide with probability proportional to exp(log_weights[n]). Requires at least
// one weight.
GuideChoice choose_guide(std::span<const double> log_weights, Rng& rng);

// The same rule for weights given as similarity products (weight n = exp(weights[n].log())),
// without a log and an exp per guide when every weight is a plain positive double; else
// the log-weight functions above decide (zero and NaN weights included). The choice's
// log_probability is exactly guide_log_probability(weights, index).
GuideChoice choose_guide(std::span<const SimilarityProduct> weights, Rng& rng);
double guide_log_probability(std::span<const SimilarityProduct> weights, size_t index);

// The same two for weights that are all plain positive doubles (each >= kRenormalise), the
// values of SimilarityProducts that are plain: the same choice and log probability, bit for
// bit, without the products.
GuideChoice choose_guide_from_plain(std::span<const double> weights, Rng& rng);
double guide_log_probability_from_plain(std::span<const double> weights, size_t index);
// Their parts: the total of plain weights (summed as both sum them) and the inverse-CDF
// choice of an index for that total (the choice choose_guide_from_plain makes).
double plain_weight_total(std::span<const double> weights);
uint32_t choose_index_from_plain(std::span<const double> weights, double total, Rng& rng);

}  // namespace emlt::ensemble
