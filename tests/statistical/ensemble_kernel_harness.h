#pragma once
// Test harness for the Ensemble MLT kernel tests (ensemble_kernel_test.cpp): known targets
// (a 2-D Gaussian mixture, a vMF mixture on S^2), their histogram cells with exact cell
// probabilities, and the Metropolis-Hastings chain runner whose final states are tested
// against the target by chi-square.
#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "mutations/ensemble/kernels.h"
#include "support/test_support.h"

namespace emlt::ensemble_test {

using namespace emlt::ensemble;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr uint64_t kSeed = 0x5eed'e71e'2021ull;

// ---------------------------------------------------------------------------------------
// Targets.

struct PlaneComponent {
  double weight;
  glm::dvec2 mean;
  double var_x, cov_xy, var_y;
};

class PlaneMixture {
 public:
  explicit PlaneMixture(std::vector<PlaneComponent> components)
      : components_(std::move(components)) {}

  Vec2 sample(Rng& rng) const {
    const PlaneComponent& c = pick(rng);
    const double r = std::sqrt(-2.0 * std::log(1.0 - rng.uniform_double()));
    const double angle = 2.0 * kPi * rng.uniform_double();
    const double n1 = r * std::cos(angle), n2 = r * std::sin(angle);
    const double l11 = std::sqrt(c.var_x), l21 = c.cov_xy / l11;
    const double l22 = std::sqrt(c.var_y - l21 * l21);
    return Vec2(c.mean + glm::dvec2(l11 * n1, l21 * n1 + l22 * n2));
  }
  double density(double x, double y) const {
    double total = 0.0;
    for (const PlaneComponent& c : components_) {
      const double det = c.var_x * c.var_y - c.cov_xy * c.cov_xy;
      const double dx = x - c.mean.x, dy = y - c.mean.y;
      const double q = (c.var_y * dx * dx - 2.0 * c.cov_xy * dx * dy + c.var_x * dy * dy) / det;
      total += c.weight * std::exp(-0.5 * q) / (2.0 * kPi * std::sqrt(det));
    }
    return total;
  }
  double log_density(const Vec2& p) const { return std::log(density(p.x, p.y)); }

 private:
  const PlaneComponent& pick(Rng& rng) const {
    double u = rng.uniform_double();
    for (const PlaneComponent& c : components_)
      if ((u -= c.weight) < 0.0) return c;
    return components_.back();
  }
  std::vector<PlaneComponent> components_;
};

inline PlaneMixture plane_target() {
  return PlaneMixture({{0.5, {-1.2, -0.6}, 0.5, 0.3, 0.4},
                       {0.3, {1.4, 0.9}, 0.15, -0.05, 0.6},
                       {0.2, {0.5, -1.8}, 0.8, 0.0, 0.1}});
}

// Square grid over [-extent, extent]^2; the last cell is everything outside it.
struct PlaneGrid {
  double extent = 4.0;
  int resolution = 24;
  int cell_count() const { return resolution * resolution + 1; }
  int cell_of(double x, double y) const {
    const double fx = (x + extent) / (2.0 * extent), fy = (y + extent) / (2.0 * extent);
    if (!(fx >= 0.0 && fx < 1.0 && fy >= 0.0 && fy < 1.0)) return resolution * resolution;
    return static_cast<int>(fy * resolution) * resolution + static_cast<int>(fx * resolution);
  }
  std::vector<double> probabilities(const std::function<double(double, double)>& density) const {
    std::vector<double> p(cell_count(), 0.0);
    const double size = 2.0 * extent / resolution;
    double inside = 0.0;
    for (int j = 0; j < resolution; ++j)
      for (int i = 0; i < resolution; ++i) {
        const double x0 = -extent + i * size, y0 = -extent + j * size;
        p[j * resolution + i] = test::integrate_2d(density, x0, x0 + size, y0, y0 + size, 8);
        inside += p[j * resolution + i];
      }
    p.back() = std::max(0.0, 1.0 - inside);
    return p;
  }
};

struct Lobe {
  double weight;
  Vec3 mean;
  double concentration;
};

class SphereMixture {
 public:
  explicit SphereMixture(std::vector<Lobe> lobes) : lobes_(std::move(lobes)) {
    for (Lobe& l : lobes_) l.mean = glm::normalize(l.mean);
  }
  Vec3 sample(Rng& rng) const {
    double u = rng.uniform_double();
    for (const Lobe& l : lobes_)
      if ((u -= l.weight) < 0.0) return sample_vmf(l.mean, l.concentration, rng);
    return sample_vmf(lobes_.back().mean, lobes_.back().concentration, rng);
  }
  double density(const glm::dvec3& w) const {
    double total = 0.0;
    for (const Lobe& l : lobes_)
      total += l.weight * std::exp(vmf_log_pdf(l.concentration, glm::dot(glm::dvec3(l.mean), w)));
    return total;
  }
  double log_density(const Vec3& w) const {
    return std::log(density(glm::normalize(glm::dvec3(w))));
  }

 private:
  std::vector<Lobe> lobes_;
};

inline SphereMixture sphere_target() {
  return SphereMixture({{0.5, {0.3f, 0.2f, 0.93f}, 12.0},
                        {0.3, {-0.7f, 0.5f, -0.2f}, 5.0},
                        {0.2, {0.2f, -0.9f, 0.1f}, 30.0}});
}

// Equal-area cells: uniform in z = cos(theta) and in phi (dw = dz dphi).
struct SphereGrid {
  int z_bins = 16, phi_bins = 32;
  int cell_count() const { return z_bins * phi_bins; }
  int cell_of(const Vec3& w) const {
    const glm::dvec3 d = glm::normalize(glm::dvec3(w));
    const int iz = std::clamp(static_cast<int>((d.z + 1.0) * 0.5 * z_bins), 0, z_bins - 1);
    const double phi = std::atan2(d.y, d.x) + kPi;
    const int ip = std::clamp(static_cast<int>(phi / (2.0 * kPi) * phi_bins), 0, phi_bins - 1);
    return iz * phi_bins + ip;
  }
  std::vector<double> probabilities(const SphereMixture& target) const {
    auto density = [&](double z, double phi) {
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      return target.density({r * std::cos(phi - kPi), r * std::sin(phi - kPi), z});
    };
    std::vector<double> p(cell_count());
    const double dz = 2.0 / z_bins, dphi = 2.0 * kPi / phi_bins;
    for (int iz = 0; iz < z_bins; ++iz)
      for (int ip = 0; ip < phi_bins; ++ip)
        p[iz * phi_bins + ip] = test::integrate_2d(density, -1.0 + iz * dz, -1.0 + (iz + 1) * dz,
                                                   ip * dphi, (ip + 1) * dphi, 8);
    return p;
  }
};

// ---------------------------------------------------------------------------------------
// The MH harness.

template <class State>
struct Step {
  State state;
  double log_ratio = 0.0;  // log T(y->x) - log T(x->y) + log P(n|y) - log P(n|x)
  bool valid = false;      // false: the kernel itself rejects (no move)
};

struct ChainReport {
  test::ChiSquareResult chi_square;
  double acceptance = 0.0;
  double moved_fraction = 0.0;
};

// Runs `chains` independent chains of `steps` MH steps (stream per chain: deterministic
// whatever the thread count) and tests the final states against the cell probabilities.
template <class State, class Target, class Kernel, class CellOf>
ChainReport run_chains(const char* label, const Target& target, const Kernel& kernel,
                       const CellOf& cell_of, const std::vector<double>& cell_probabilities,
                       int chains, int steps) {
  std::vector<int> final_cell(chains);
  std::vector<int> accepted(chains), moved(chains);
  tbb::parallel_for(tbb::blocked_range<int>(0, chains, 512),
                    [&](const tbb::blocked_range<int>& range) {
                      Kernel local_kernel = kernel;  // its own scratch buffers
                      for (int chain = range.begin(); chain != range.end(); ++chain) {
                        Rng rng = Rng::for_item(kSeed, static_cast<uint64_t>(chain));
                        const State start = target.sample(rng);
                        State x = start;
                        double log_pi_x = target.log_density(x);
                        for (int s = 0; s < steps; ++s) {
                          const Step<State> step = local_kernel(x, rng);
                          const double u = rng.uniform_double();
                          if (!step.valid) continue;
                          const double log_pi_y = target.log_density(step.state);
                          const double log_acceptance = log_pi_y - log_pi_x + step.log_ratio;
                          if (std::log(u) < log_acceptance) {
                            x = step.state;
                            log_pi_x = log_pi_y;
                            ++accepted[chain];
                          }
                        }
                        final_cell[chain] = cell_of(x);
                        moved[chain] = x != start;
                      }
                    });
  std::vector<double> observed(cell_probabilities.size(), 0.0), expected(cell_probabilities.size());
  double total_accepted = 0.0, total_moved = 0.0;
  for (int c = 0; c < chains; ++c) {
    observed[final_cell[c]] += 1.0;
    total_accepted += accepted[c];
    total_moved += moved[c];
  }
  for (size_t i = 0; i < expected.size(); ++i) expected[i] = cell_probabilities[i] * chains;
  ChainReport report;
  report.chi_square = test::chi_square_test(observed, expected, std::max(5.0, 1e-3 * chains));
  report.acceptance = total_accepted / (static_cast<double>(chains) * steps);
  report.moved_fraction = total_moved / chains;
  std::printf("[%s] chi2 = %.1f (dof %d) p = %.3g, acceptance %.3f, moved %.3f\n", label,
              report.chi_square.statistic, report.chi_square.degrees_of_freedom,
              report.chi_square.p_value, report.acceptance, report.moved_fraction);
  return report;
}

inline void expect_matches_target(const ChainReport& report) {
  EXPECT_GT(report.chi_square.p_value, 1e-3);
  EXPECT_GT(report.acceptance, 0.05);
  EXPECT_GT(report.moved_fraction, 0.6);
}

inline void expect_detected(const ChainReport& report) {
  EXPECT_LT(report.chi_square.p_value, 1e-6);
}

template <class T>
std::vector<T> frozen_guides(const auto& target, int count, uint64_t stream) {
  Rng rng(kSeed, stream);
  std::vector<T> guides;
  for (int i = 0; i < count; ++i) guides.push_back(target.sample(rng));
  return guides;
}
}  // namespace emlt::ensemble_test
