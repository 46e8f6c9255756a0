#include "emlt/run/pixel_state.h"

#include <algorithm>

#include "emlt/core/cluster.h"

namespace emlt {

void PixelRenderState::save(StateWriter& out) const {
  out.put_vector(sums);
  out.put_vector(counts);
  out.put(schedule);
  out.put(invalid);
}

void PixelRenderState::load(StateReader& in, int width, int height) {
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  sums = in.get_vector<DVec3>(pixels);
  counts = in.get_vector<int32_t>(pixels);
  schedule = in.get<PassSchedule::Saved>();
  invalid = in.get<uint64_t>();
  for (uint64_t i = 0; i < pixels; ++i) {
    const int32_t c = counts[i];
    const bool valid = owns_row(int(i / uint64_t(width)))
                           ? c >= schedule.done && c <= std::max(schedule.done, schedule.pass_end)
                           : c == 0;
    if (!valid) throw StateError("a pixel's sample count lies outside the pass under way");
  }
  resumed = true;
}

PixelRenderState::Totals PixelRenderState::totals() const {
  Totals t;
  t.sums.resize(3 * sums.size());
  for (size_t i = 0; i < sums.size(); ++i)
    for (int c = 0; c < 3; ++c) t.sums[3 * i + size_t(c)] = sums[i][c];
  t.counts = counts;
  // Each pixel is some one rank's: the others add +0.0 and 0, which changes no bit.
  cluster::sum_to_root(t.sums);
  cluster::sum_to_root(t.counts);
  return t;
}

Image PixelRenderState::Totals::image(int width, int height) const {
  Image image(width, height);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] =
        counts[i] > 0
            ? Rgb(DVec3(sums[3 * i], sums[3 * i + 1], sums[3 * i + 2]) / double(counts[i]))
            : Rgb(0.0f);
  return image;
}

uint64_t PixelRenderState::Totals::samples() const {
  uint64_t total = 0;
  for (const int32_t c : counts) total += uint64_t(c);
  return total;
}

bool PixelRenderState::behind(int samples, int width) const {
  const size_t rows = width > 0 ? counts.size() / size_t(width) : 0;
  for (size_t y = 0; y < rows; ++y) {
    if (!owns_row(int(y))) continue;
    const int32_t* row = &counts[y * size_t(width)];
    if (std::any_of(row, row + width, [&](int32_t c) { return c < samples; })) return true;
  }
  return false;
}

// Bands of 16 rows, not tied to the tile size (pass_runner.cpp): a tile skips the rows of
// other ranks' bands, and a 16-row tile belongs to the rank of its first row.
constexpr int kRankBandRows = 16;

bool owns_row(int y) {
  return (y / kRankBandRows) % cluster::size() == cluster::rank();
}

}  // namespace emlt
