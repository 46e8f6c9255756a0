#pragma once
// The pixels that see an emitter directly, which image comparisons (`emlt compare --scene`,
// a render's convergence log) report apart: there the image is the emitter's radiance, not
// transport.
#include <cstdint>
#include <vector>

namespace emlt {

class Scene;

// Which pixels see an emitter (area light or environment) directly: any of a 3x3 grid of
// primary rays through the pixel hits one. One entry per pixel, row by row.
std::vector<uint8_t> directly_visible_emitters(const Scene& scene);

}  // namespace emlt
