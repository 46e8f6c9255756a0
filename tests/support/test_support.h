#pragma once
// Shared helpers for the test suites: repository paths, the chi-square goodness-of-fit
// test used for every sampler, and temporary directories and the files written into them.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace emlt::test {

// Absolute path of a file in the repository ("scenes/cornell-box/scene.json").
std::string source_path(const std::string& relative);
// Path of the built `emlt` executable.
std::string emlt_binary();
// A fresh, empty directory under the build tree, unique per test.
std::filesystem::path scratch_dir(const std::string& name);
// Writes `bytes` (text or binary, unchanged) to dir/name and returns the file's path.
std::string write_file(const std::filesystem::path& dir, const std::string& name,
                       const std::string& bytes);

// The message of the emlt::Error that f throws ("" when it throws none).
std::string error_of(const std::function<void()>& f);

// Runs a shell command, returns its exit status; stdout+stderr go to `output`.
int run_command(const std::string& command, std::string* output = nullptr);

struct ChiSquareResult {
  double statistic = 0.0;
  int degrees_of_freedom = 0;
  double p_value = 0.0;
  int pooled_cells = 0;  // low-expectation cells merged into one
};

// Pearson chi-square test of observed counts against expected counts (same total).
// Cells with expected < min_expected are pooled, as in Mitsuba's and pbrt's tests.
// An observed count in a cell with zero expectation yields p_value = 0.
ChiSquareResult chi_square_test(const std::vector<double>& observed,
                                const std::vector<double>& expected, double min_expected = 5.0);

// Upper tail of the chi-square distribution with k degrees of freedom.
double chi_square_survival(double statistic, int k);

// Integrates f over [a,b]x[c,d] with an n x n composite Simpson rule (n even).
double integrate_2d(const std::function<double(double, double)>& f, double a, double b, double c,
                    double d, int n);

}  // namespace emlt::test
