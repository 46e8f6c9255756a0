#include "support/image_checks.h"

#include <algorithm>
#include <cmath>

namespace emlt::test {

double grey_mean(const Image& image) {
  double sum = 0.0;
  for (const Rgb& p : image.pixels) sum += (double(p.x) + double(p.y) + double(p.z)) / 3.0;
  return sum / double(image.pixels.size());
}

double worst_block_error(const Image& reference, const Image& test, int block) {
  const double floor = 0.25 * grey_mean(reference);
  double worst = 0.0;
  for (int by = 0; by + block <= reference.height; by += block) {
    for (int bx = 0; bx + block <= reference.width; bx += block) {
      double a = 0.0, b = 0.0;
      for (int y = by; y < by + block; ++y)
        for (int x = bx; x < bx + block; ++x) {
          const Rgb& p = reference.at(x, y);
          const Rgb& q = test.at(x, y);
          a += (p.x + p.y + p.z) / 3.0;
          b += (q.x + q.y + q.z) / 3.0;
        }
      const double n = double(block) * block;
      worst = std::max(worst, std::abs(a - b) / n / std::max(a / n, floor));
    }
  }
  return worst;
}

}  // namespace emlt::test
