#include "support/test_support.h"

#include "emlt/core/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <gtest/gtest.h>

namespace emlt::test {

std::string source_path(const std::string& relative) {
  return std::string(EMLT_SOURCE_DIR) + "/" + relative;
}

std::string emlt_binary() { return EMLT_BINARY; }

std::filesystem::path scratch_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string id = name;
  if (info) id = std::string(info->test_suite_name()) + "." + info->name() + "." + name;
  auto dir = std::filesystem::current_path() / "test-scratch" / id;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string write_file(const std::filesystem::path& dir, const std::string& name,
                       const std::string& bytes) {
  const auto path = dir / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

int run_command(const std::string& command, std::string* output) {
  std::string full = command + " 2>&1";
  FILE* pipe = popen(full.c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buffer{};
  std::string text;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) text.append(buffer.data(), n);
  const int status = pclose(pipe);
  if (output) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

namespace {

// Regularised lower incomplete gamma P(a, x) by its power series (x < a + 1).
double gamma_p_series(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 10000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * 1e-15) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Regularised upper incomplete gamma Q(a, x) by Lentz's continued fraction (x >= a + 1).
double gamma_q_fraction(double a, double x) {
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double chi_square_survival(double statistic, int k) {
  if (statistic <= 0.0) return 1.0;
  const double a = 0.5 * k, x = 0.5 * statistic;
  return x < a + 1.0 ? 1.0 - gamma_p_series(a, x) : gamma_q_fraction(a, x);
}

ChiSquareResult chi_square_test(const std::vector<double>& observed,
                                const std::vector<double>& expected, double min_expected) {
  ChiSquareResult result;
  std::vector<size_t> order(observed.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  double pooled_obs = 0.0, pooled_exp = 0.0;
  int cells = 0;
  for (size_t idx : order) {
    const double e = expected[idx], o = observed[idx];
    if (e <= 0.0) {
      if (o > 0.0) {
        result.p_value = 0.0;
        result.statistic = INFINITY;
        return result;
      }
      continue;
    }
    if (e < min_expected) {
      pooled_obs += o;
      pooled_exp += e;
      ++result.pooled_cells;
    } else {
      result.statistic += (o - e) * (o - e) / e;
      ++cells;
    }
  }
  if (pooled_exp > 0.0) {
    result.statistic += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++cells;
  }
  result.degrees_of_freedom = std::max(1, cells - 1);
  result.p_value = chi_square_survival(result.statistic, result.degrees_of_freedom);
  return result;
}

double integrate_2d(const std::function<double(double, double)>& f, double a, double b, double c,
                    double d, int n) {
  if (n % 2) ++n;
  const double hx = (b - a) / n, hy = (d - c) / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double wx = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    for (int j = 0; j <= n; ++j) {
      const double wy = (j == 0 || j == n) ? 1.0 : (j % 2 ? 4.0 : 2.0);
      sum += wx * wy * f(a + i * hx, c + j * hy);
    }
  }
  return sum * hx * hy / 9.0;
}

}  // namespace emlt::test
