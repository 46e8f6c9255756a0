#include "mutations/ensemble/similarity.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace emlt::ensemble {

double log_similarity_from_squared_distance(double squared_distance,
                                            const SimilarityParams& params) {
  const double scaled = squared_distance / (params.length_scale * params.length_scale);
  const double inverse_distance = 1.0 / std::max(scaled, params.epsilon);  // d of eq. 8
  // 2 / (1 + e^-d) - 1 = (1 - e^-d) / (1 + e^-d) = tanh(d / 2). For d -> 0 (far apart)
  // tanh(d/2) ~ d/2 keeps full relative precision, which the literal form would not.
  return std::log(std::tanh(0.5 * inverse_distance));
}

double log_vertex_similarity(const Vec3& a, const Vec3& b, const SimilarityParams& params) {
  const DVec3 offset = DVec3(a) - DVec3(b);
  return log_similarity_from_squared_distance(glm::dot(offset, offset), params);
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
  double total = 0.0;
  for (double w : log_weights)
    if (!std::isnan(w)) total += std::exp(w - largest);
  // Inverse CDF; the last guide with a positive weight absorbs rounding at the top end.
  const double target = rng.uniform_double() * total;
  double cumulative = 0.0;
  uint32_t chosen = 0;
  for (size_t n = 0; n < count; ++n) {
    if (std::isnan(log_weights[n])) continue;
    const double w = std::exp(log_weights[n] - largest);
    if (w <= 0.0) continue;
    chosen = static_cast<uint32_t>(n);
    cumulative += w;
    if (target < cumulative) break;
  }
  return {chosen, (log_weights[chosen] - largest) - std::log(total)};
}

}  // namespace emlt::ensemble
