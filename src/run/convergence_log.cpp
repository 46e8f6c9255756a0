#include "emlt/run/convergence_log.h"

#include <fmt/core.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "emlt/core/atomic_write.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"

namespace emlt {

ConvergenceLog::ConvergenceLog(std::string path, Image reference, std::vector<uint8_t> sees_emitter,
                               int width, int height)
    : path_(std::move(path)),
      reference_(std::move(reference)),
      sees_emitter_(std::move(sees_emitter)) {
  if (reference_.width != width || reference_.height != height)
    throw Error("reference is " + std::to_string(reference_.width) + "x" +
                std::to_string(reference_.height) + " but the render is " + std::to_string(width) +
                "x" + std::to_string(height));
}

void ConvergenceLog::snapshot(double per_pixel, double seconds, const Image& image,
                              const std::vector<StrategyAcceptance>& strategies) {
  const ImageMetrics m = compare_images(reference_, image, std::nullopt,
                                        sees_emitter_.empty() ? nullptr : &sees_emitter_);
  if (header_.empty()) {
    header_ = "per_pixel,seconds,mse,relmse,mse_no_emitter,mean_ratio";
    for (const auto& s : strategies) header_ += ",acceptance_" + s.name;
  }
  std::string row = fmt::format(
      "{:.6g},{:.6g},{:.8g},{:.8g},{},{:.8g}", per_pixel, seconds, m.mse, m.rel_mse,
      std::isnan(m.mse_no_emitter) ? std::string("") : fmt::format("{:.8g}", m.mse_no_emitter),
      m.mean_ratio);
  for (const auto& s : strategies) row += fmt::format(",{:.6g}", s.mean_acceptance);
  rows_.push_back(std::move(row));
  write();
}

void ConvergenceLog::write() const {
  std::string text = header_ + "\n";
  for (const auto& row : rows_) text += row + "\n";
  write_file_atomically(path_, "the convergence log", text);
}

}  // namespace emlt
