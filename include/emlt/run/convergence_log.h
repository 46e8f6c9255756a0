#pragma once
// `--reference REF --log FILE.csv`: one row per snapshot with samples (mutations) per
// pixel, seconds, MSE, relMSE, MSE over pixels that see no emitter, the mean ratio to the
// reference and, for MLT, each strategy's mean acceptance. The file is rewritten
// atomically after every row, so a crashed render leaves the rows so far.
#include <string>
#include <vector>

#include "emlt/image/image_metrics.h"
#include "emlt/run/snapshot.h"

namespace emlt {

class ConvergenceLog final : public SnapshotSink {
 public:
  // Throws emlt::Error if the reference's size differs from width x height.
  ConvergenceLog(std::string path, Image reference, std::vector<uint8_t> sees_emitter, int width,
                 int height);
  void snapshot(double per_pixel, double seconds, const Image& image,
                const std::vector<StrategyAcceptance>& strategies) override;
  size_t rows() const { return rows_.size(); }

  // Checkpoints keep the rows so far, so a resumed render's log holds the whole run.
  const std::string& header() const { return header_; }
  const std::vector<std::string>& row_texts() const { return rows_; }
  void restore(std::string header, std::vector<std::string> rows) {
    header_ = std::move(header);
    rows_ = std::move(rows);
  }

 private:
  void write() const;

  std::string path_;
  Image reference_;
  std::vector<uint8_t> sees_emitter_;
  std::string header_;
  std::vector<std::string> rows_;
};

}  // namespace emlt
