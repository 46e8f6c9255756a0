#include "mutations/ensemble/similarity.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <optional>

#include "mutations/ensemble/guide_lanes.h"

namespace emlt::ensemble {

double log_vertex_similarity(const Vec3& a, const Vec3& b, const SimilarityParams& params) {
  return std::log(vertex_similarity(a, b, params));
}

double log_vertex_similarity(const Vec2& a, const Vec2& b, const SimilarityParams& params) {
  const glm::dvec2 offset = glm::dvec2(a) - glm::dvec2(b);
  return log_similarity_from_squared_distance(glm::dot(offset, offset), params);
}

double log_path_similarity(std::span<const Vec3> path_vertices,
                           std::span<const Vec3> guide_vertices, const SimilarityParams& params) {
  assert(path_vertices.size() == guide_vertices.size());
  double log_product = 0.0;  // eq. 9's product, as a sum of logs
  for (size_t i = 0; i < path_vertices.size(); ++i)
    log_product += log_vertex_similarity(path_vertices[i], guide_vertices[i], params);
  return log_product;
}

namespace {

// Four guides at a time (GCC's vector extensions: one SSE register of floats on x86-64's
// baseline). Each lane runs exactly the operations of the scalar forms in similarity.h in
// the same order, so a row equals vertex_similarity bit for bit (the unit test checks it).
using Float4 = float __attribute__((vector_size(16)));
using Bits4 = uint32_t __attribute__((vector_size(16)));

[[gnu::always_inline]] inline Float4 splat4(float value) {
  return Float4{value, value, value, value};
}
// mask ? a : b, for a mask of all-ones / all-zeros lanes (a vector comparison's result).
[[gnu::always_inline]] inline Float4 select4(Bits4 mask, Float4 a, Float4 b) {
  return Float4((Bits4(a) & mask) | (Bits4(b) & ~mask));
}

[[gnu::always_inline]] inline Float4 far_similarity4(Float4 floored) {
  const Float4 half_d = 0.5f * (1.0f / floored);
  const Float4 y2 = half_d * half_d;
  return half_d * (1.0f + y2 * (-1.0f / 3.0f + y2 * (2.0f / 15.0f)));
}

[[gnu::always_inline]] inline Float4 middle_similarity4(Float4 floored) {
  const Float4 x = -1.0f / floored;
  constexpr float kInverseLn2 = 1.44269504f;
  constexpr float kLn2High = 0.693359375f;
  constexpr float kLn2Low = -2.12194440e-4f;
  constexpr float kRoundShift = 0x1.8p23f;
  const Float4 shifted = x * kInverseLn2 + kRoundShift;
  const Float4 k = shifted - kRoundShift;
  const Float4 r = (x - k * kLn2High) - k * kLn2Low;
  const Float4 q =
      1.0f / 2 +
      r * (1.0f / 6 + r * (1.0f / 24 + r * (1.0f / 120 + r * (1.0f / 720 + r * (1.0f / 5040)))));
  const Float4 expm1_r = r + r * r * q;
  const Bits4 k_bits = Bits4(shifted) - std::bit_cast<uint32_t>(kRoundShift);
  const Float4 power = Float4((k_bits + 127) << 23);
  const Float4 t = power * expm1_r + (power - 1.0f);
  return -t / (t + 2.0f);
}

// Two guides' coordinates at a time in double (SSE2's two lanes), four guides' similarities
// in float. Each lane runs exactly the scalar operations, in the same order.
using Float2 = float __attribute__((vector_size(8)));

// The floored squared distances of guides n, n + 1 as vertex_similarity computes them (in
// double; glm::dot sums (x^2 + y^2) + z^2; std::max(scaled, epsilon)).
template <bool kScaled>
[[gnu::always_inline]] inline Double2 floored2(const Double2 (&point)[3], const double* x,
                                               const double* y, const double* z, size_t n,
                                               double length_squared, double epsilon) {
  const Double2 dx = point[0] - load2(x + n), dy = point[1] - load2(y + n),
                dz = point[2] - load2(z + n);
  const Double2 squared = dx * dx + dy * dy + dz * dz;
  const Double2 scaled = kScaled ? squared / length_squared : squared;
  return scaled < epsilon ? Double2{epsilon, epsilon} : scaled;
}

// eq. 8 for four floored distances rounded to float: the far range first (when paths do not
// run close to each other it holds every guide), the others only when some lane needs them.
[[gnu::always_inline]] inline Float4 similarity4(Float4 f) {
  const Float4 far = far_similarity4(f);
  const Bits4 is_far = Bits4(f > kFarSimilarity);  // NaN counts as not far, as in the scalar form
  if ((is_far[0] & is_far[1] & is_far[2] & is_far[3]) != 0) return far;
  const Float4 near_or_middle =
      select4(Bits4(f < kNearSimilarity), splat4(1.0f), middle_similarity4(f));
  return select4(is_far, far, near_or_middle);
}

template <bool kScaled>
void similarity_row(const Vec3& point, const double* x, const double* y, const double* z,
                    const SimilarityParams& params, double* out, size_t count) {
  const double length_squared = params.length_scale * params.length_scale;
  const double epsilon = params.epsilon;
  const Double2 p[3] = {Double2{point.x, point.x}, Double2{point.y, point.y},
                        Double2{point.z, point.z}};
  size_t n = 0;
  for (; n + 4 <= count; n += 4) {
    const Float2 low =
        __builtin_convertvector(floored2<kScaled>(p, x, y, z, n, length_squared, epsilon), Float2);
    const Float2 high = __builtin_convertvector(
        floored2<kScaled>(p, x, y, z, n + 2, length_squared, epsilon), Float2);
    const Float4 similarity = similarity4(__builtin_shufflevector(low, high, 0, 1, 2, 3));
    store2(out + n,
           __builtin_convertvector(__builtin_shufflevector(similarity, similarity, 0, 1), Double2));
    store2(out + n + 2,
           __builtin_convertvector(__builtin_shufflevector(similarity, similarity, 2, 3), Double2));
  }
  if (n == count) return;
  // The last one to three guides; the lanes past the end hold f = 1 (any value would do).
  Float4 floored = splat4(1.0f);
  for (size_t j = 0; n + j < count; ++j) {
    const double dx = double(point.x) - x[n + j], dy = double(point.y) - y[n + j],
                 dz = double(point.z) - z[n + j];
    const double squared = dx * dx + dy * dy + dz * dz;
    const double scaled = kScaled ? squared / length_squared : squared;
    floored[j] = float(scaled < epsilon ? epsilon : scaled);
  }
  const Float4 similarity = similarity4(floored);
  for (size_t j = 0; n + j < count; ++j) out[n + j] = double(similarity[j]);
}

}  // namespace

void similarities_to_guides(const Vec3& point, std::span<const double> x, std::span<const double> y,
                            std::span<const double> z, const SimilarityParams& params,
                            std::span<double> out) {
  assert(x.size() == out.size() && y.size() == out.size() && z.size() == out.size());
  // Each group of four guides stays in registers from the coordinates to the similarities:
  // rows through arrays of floored distances and of similarities cost twice as much
  // (docs/experiments.md, "Cost per mutation").
  if (params.length_scale * params.length_scale == 1.0)
    similarity_row<false>(point, x.data(), y.data(), z.data(), params, out.data(), out.size());
  else
    similarity_row<true>(point, x.data(), y.data(), z.data(), params, out.data(), out.size());
}

void log_similarities_to_guides(const Vec3& point, std::span<const Vec3> guides,
                                const SimilarityParams& params, std::span<double> out) {
  assert(out.size() == guides.size());
  for (size_t n = 0; n < guides.size(); ++n)
    out[n] = log_vertex_similarity(point, guides[n], params);
}

void log_similarities_to_guides(const Vec2& point, std::span<const Vec2> guides,
                                const SimilarityParams& params, std::span<double> out) {
  assert(out.size() == guides.size());
  for (size_t n = 0; n < guides.size(); ++n)
    out[n] = log_vertex_similarity(point, guides[n], params);
}

double normalise_log_weights(std::span<const double> log_weights, std::span<double> probabilities) {
  assert(probabilities.size() == log_weights.size());
  const size_t count = log_weights.size();
  if (count == 0) return 0.0;
  double largest = -std::numeric_limits<double>::infinity();
  for (double w : log_weights)
    if (w > largest) largest = w;  // NaN never compares greater
  if (!std::isfinite(largest)) {
    // No usable weight (all zero, or an infinite/NaN one): uniform, decided from the weights.
    std::fill(probabilities.begin(), probabilities.end(), 1.0 / static_cast<double>(count));
    return static_cast<double>(count);
  }
  double total = 0.0;
  for (size_t n = 0; n < count; ++n) {
    const double w = std::isnan(log_weights[n]) ? 0.0 : std::exp(log_weights[n] - largest);
    probabilities[n] = w;
    total += w;
  }
  double sum_of_squares = 0.0;
  for (double& p : probabilities) {
    p /= total;  // total >= 1: the largest term contributes exp(0)
    sum_of_squares += p * p;
  }
  return 1.0 / sum_of_squares;
}

double guide_log_probability(std::span<const double> log_weights, size_t index) {
  assert(index < log_weights.size());
  double largest = -std::numeric_limits<double>::infinity();
  for (double w : log_weights)
    if (w > largest) largest = w;
  if (!std::isfinite(largest)) return -std::log(static_cast<double>(log_weights.size()));
  if (std::isnan(log_weights[index])) return -std::numeric_limits<double>::infinity();
  double total = 0.0;
  for (double w : log_weights)
    if (!std::isnan(w)) total += std::exp(w - largest);
  return (log_weights[index] - largest) - std::log(total);
}

GuideChoice choose_guide(std::span<const double> log_weights, Rng& rng) {
  assert(!log_weights.empty());
  const size_t count = log_weights.size();
  double largest = -std::numeric_limits<double>::infinity();
  for (double w : log_weights)
    if (w > largest) largest = w;
  if (!std::isfinite(largest)) {
    const uint32_t index = rng.uniform_index(static_cast<uint32_t>(count));
    return {index, -std::log(static_cast<double>(count))};
  }
  // The shifted weights once, for the total and the inverse CDF.
  GuideBuffer<double> weights(count);
  double total = 0.0;
  for (size_t n = 0; n < count; ++n) {
    weights[n] = std::isnan(log_weights[n]) ? 0.0 : std::exp(log_weights[n] - largest);
    total += weights[n];
  }
  // Inverse CDF; the last guide with a positive weight absorbs rounding at the top end.
  const double target = rng.uniform_double() * total;
  double cumulative = 0.0;
  uint32_t chosen = 0;
  for (size_t n = 0; n < count; ++n) {
    if (!(weights[n] > 0.0)) continue;
    chosen = static_cast<uint32_t>(n);
    cumulative += weights[n];
    if (target < cumulative) break;
  }
  return {chosen, (log_weights[chosen] - largest) - std::log(total)};
}

namespace {

// The sum of the weights if every weight can be used as it is (plain and positive): then
// P(n) = w_n / sum w. Four partial sums, so that the additions do not wait on each other.
std::optional<double> plain_total(std::span<const SimilarityProduct> weights) {
  std::array<double, 4> partial{};
  bool plain = true;
  const auto add = [&](size_t n, size_t lane) {
    plain &= weights[n].is_plain() && weights[n].plain() > 0.0;
    partial[lane] += weights[n].plain();
  };
  // Unrolled by the four partial sums (partial[n % 4] gets the same terms in the same
  // order): the loop with n % 4 took 15 instructions a weight.
  const size_t count = weights.size(), quads = count & ~size_t(3);
  for (size_t n = 0; n < quads; n += 4) {
    add(n, 0);
    add(n + 1, 1);
    add(n + 2, 2);
    add(n + 3, 3);
  }
  for (size_t n = quads; n < count; ++n) add(n, n - quads);
  if (!plain) return std::nullopt;
  return (partial[0] + partial[1]) + (partial[2] + partial[3]);
}

void logs_of(std::span<const SimilarityProduct> weights, std::span<double> out) {
  for (size_t n = 0; n < weights.size(); ++n) out[n] = weights[n].log();
}

}  // namespace

NormalisedWeights normalise_weights(std::span<const SimilarityProduct> weights,
                                    std::span<double> probabilities) {
  assert(probabilities.size() == weights.size());
  const std::optional<double> total = plain_total(weights);
  if (!total) {
    GuideBuffer<double> log_weights(weights.size());
    logs_of(weights, log_weights.span());
    const double largest = *std::max_element(log_weights.span().begin(), log_weights.span().end());
    return {normalise_log_weights(log_weights.span(), probabilities), std::isfinite(largest)};
  }
  double sum_of_squares = 0.0;
  for (size_t n = 0; n < weights.size(); ++n) {
    probabilities[n] = weights[n].plain() / *total;
    sum_of_squares += probabilities[n] * probabilities[n];
  }
  return {1.0 / sum_of_squares, true};
}

namespace {

// plain_total's sum for weights given as doubles: the same four partial sums, the same order.
double plain_sum(std::span<const double> weights) {
  std::array<double, 4> partial{};
  const size_t count = weights.size(), quads = count & ~size_t(3);
  for (size_t n = 0; n < quads; n += 4) {
    partial[0] += weights[n];
    partial[1] += weights[n + 1];
    partial[2] += weights[n + 2];
    partial[3] += weights[n + 3];
  }
  for (size_t n = quads; n < count; ++n) partial[n - quads] += weights[n];
  return (partial[0] + partial[1]) + (partial[2] + partial[3]);
}

}  // namespace

NormalisedWeights normalise_row_products(std::span<const double> first,
                                         std::span<const double> second,
                                         std::span<double> probabilities) {
  const size_t count = first.size();
  assert(probabilities.size() == count && (second.empty() || second.size() == count));
  constexpr double kRenormalise = SimilarityProduct::kRenormalise;
  // The weights into `probabilities` first; plain as SimilarityProduct::multiply keeps a
  // product plain: every factor and the product >= kRenormalise (false for NaN). Each test a
  // loop of its own, so that it vectorises.
  bool plain = all_at_least(first, kRenormalise);
  if (second.empty()) {
    std::copy(first.begin(), first.end(), probabilities.begin());
  } else {
    for (size_t n = 0; n < count; ++n) probabilities[n] = first[n] * second[n];
    plain &= all_at_least(second, kRenormalise);
    plain &= all_at_least(probabilities, kRenormalise);
  }
  if (!plain) {
    GuideBuffer<SimilarityProduct> products(count);
    for (size_t n = 0; n < count; ++n) {
      products[n] = SimilarityProduct{};
      products[n].multiply(first[n]);
      if (!second.empty()) products[n].multiply(second[n]);
    }
    return normalise_weights(std::span<const SimilarityProduct>(products.span()), probabilities);
  }
  const double total = plain_sum(probabilities);
  for (size_t n = 0; n < count; ++n) probabilities[n] = probabilities[n] / total;
  double sum_of_squares = 0.0;  // in order, as before
  for (size_t n = 0; n < count; ++n) sum_of_squares += probabilities[n] * probabilities[n];
  return {1.0 / sum_of_squares, true};
}

GuideChoice choose_guide(std::span<const SimilarityProduct> weights, Rng& rng) {
  assert(!weights.empty());
  const std::optional<double> total = plain_total(weights);
  if (!total) {
    GuideBuffer<double> log_weights(weights.size());
    logs_of(weights, log_weights.span());
    return choose_guide(log_weights.span(), rng);
  }
  // Inverse CDF; the last guide absorbs rounding at the top end.
  const double target = rng.uniform_double() * *total;
  double cumulative = 0.0;
  uint32_t chosen = 0;
  for (size_t n = 0; n < weights.size(); ++n) {
    chosen = static_cast<uint32_t>(n);
    cumulative += weights[n].plain();
    if (target < cumulative) break;
  }
  return {chosen, std::log(weights[chosen].plain()) - std::log(*total)};
}

double guide_log_probability(std::span<const SimilarityProduct> weights, size_t index) {
  assert(index < weights.size());
  const std::optional<double> total = plain_total(weights);
  if (!total) {
    GuideBuffer<double> log_weights(weights.size());
    logs_of(weights, log_weights.span());
    return guide_log_probability(log_weights.span(), index);
  }
  return std::log(weights[index].plain()) - std::log(*total);
}

double plain_weight_total(std::span<const double> weights) {
  return plain_sum(weights);
}

uint32_t choose_index_from_plain(std::span<const double> weights, double total, Rng& rng) {
  // As choose_guide's plain branch: inverse CDF, the last guide absorbing rounding.
  const double target = rng.uniform_double() * total;
  double cumulative = 0.0;
  uint32_t chosen = 0;
  for (size_t n = 0; n < weights.size(); ++n) {
    chosen = static_cast<uint32_t>(n);
    cumulative += weights[n];
    if (target < cumulative) break;
  }
  return chosen;
}

GuideChoice choose_guide_from_plain(std::span<const double> weights, Rng& rng) {
  assert(!weights.empty());
  const double total = plain_sum(weights);
  const uint32_t chosen = choose_index_from_plain(weights, total, rng);
  return {chosen, std::log(weights[chosen]) - std::log(total)};
}

double guide_log_probability_from_plain(std::span<const double> weights, size_t index) {
  assert(index < weights.size());
  return std::log(weights[index]) - std::log(plain_sum(weights));
}

}  // namespace emlt::ensemble
