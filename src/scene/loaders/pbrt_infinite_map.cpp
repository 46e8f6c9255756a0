// pbrt-v4's image infinite light: its radiance is stored on an equal-area octahedral square
// (Clarberg 2008, pbrt-v4's EqualAreaSphereToSquare), in the light's frame (z up there).
// emlt's environment maps are lat-long, so the image is resampled onto one, bilinearly,
// at the same texel count (an approximated item: the resampling blurs by about a texel).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "emlt/core/warp.h"
#include "emlt/image/image.h"
#include "src/scene/loaders/pbrt_reader.h"

namespace emlt::pbrt {

namespace {

// The point of the unit square that pbrt-v4 stores direction d at (d of unit length).
Vec2 equal_area_sphere_to_square(const Vec3& d) {
  const float x = std::abs(d.x), y = std::abs(d.y), z = std::abs(d.z);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z));
  const float a = std::max(x, y), b = std::min(x, y);
  float phi = (a == 0.0f ? 0.0f : std::atan(b / a)) * 2.0f / kPi;
  if (x < y) phi = 1.0f - phi;
  float v = phi * r, u = r - v;
  if (d.z < 0.0f) {
    std::swap(u, v);
    u = 1.0f - u;
    v = 1.0f - v;
  }
  u = std::copysign(u, d.x);
  v = std::copysign(v, d.y);
  return Vec2((u + 1.0f) * 0.5f, (v + 1.0f) * 0.5f);
}

// Bilinear lookup, texel centres at (i + 0.5) / size, row 0 at the top (as pbrt's images),
// clamped at the border (pbrt wraps the octahedron there: within half a texel of the
// edge the two differ).
Rgb bilinear(const Image& image, const Vec2& uv) {
  const float x = uv.x * float(image.width) - 0.5f, y = uv.y * float(image.height) - 0.5f;
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const float fx = x - float(x0), fy = y - float(y0);
  auto at = [&](int i, int j) {
    return image.at(std::clamp(i, 0, image.width - 1), std::clamp(j, 0, image.height - 1));
  };
  return (1.0f - fy) * ((1.0f - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
         fy * ((1.0f - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

}  // namespace

void Reader::infinite_map(const Where& at, const std::string& file_name, float scale) {
  const std::string file = resolve(at, file_name);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    fail(at, "LightSource \"infinite\": image '" + file_name + "' not found");
  const Image square = read_image(file);
  if (square.width != square.height || square.width < 1)
    fail(at, fmt::format("LightSource \"infinite\": '{}' is {}x{}; pbrt's maps are square "
                         "(equal-area octahedral)",
                         file_name, square.width, square.height));
  // Directions go from the world to the light's frame by the inverse of the matrix at
  // LightSource (pbrt's renderFromLight).
  const Mat3 to_light = glm::inverse(Mat3(state_.ctm));
  const int n = square.width;
  Image latlong(2 * n, n);
  for (int j = 0; j < latlong.height; ++j)
    for (int i = 0; i < latlong.width; ++i) {
      const Vec2 uv((float(i) + 0.5f) / float(latlong.width),
                    (float(j) + 0.5f) / float(latlong.height));
      const Vec3 d = glm::normalize(to_light * latlong_to_direction(uv));
      latlong.at(i, j) = bilinear(square, equal_area_sphere_to_square(d));
    }
  EnvironmentDesc& env = desc_.environment;
  env.kind = EnvironmentDesc::Kind::Map;
  env.map_path = file;
  env.map = std::move(latlong);
  env.scale = scale;
  env.to_world = Mat4(1.0f);
  warn(at,
       fmt::format("LightSource \"infinite\": '{}' resampled from pbrt's equal-area "
                   "octahedral map onto a {}x{} lat-long map (bilinear)",
                   file_name, 2 * n, n),
       Divergence::Kind::Approximated);
}

}  // namespace emlt::pbrt
