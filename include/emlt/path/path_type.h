#pragma once
// Heckbert's regular-expression notation for a path x0 ... xk read from the light:
// "L D D S E" (L = emitter, E = eye, S = a Dirac interaction, D = anything else, glossy
// included). MLT perturbations are chosen by it and EMLT's path-type tree is keyed by it,
// so it is computed once per path and kept as a compact, hashable value.
#include <cstdint>
#include <functional>
#include <string>

namespace emlt {

struct PathType {
  static constexpr int kMaxVertices = 64;  // interior vertices fit the 64-bit mask

  uint64_t specular_mask = 0;  // bit i set: interior vertex x_i is S (bit 0 = x0, always 0)
  uint8_t vertices = 0;        // k + 1

  int edges() const { return int(vertices) - 1; }
  bool is_specular(int i) const { return i > 0 && i < 64 && ((specular_mask >> i) & 1u) != 0; }
  // "L D S E"; an empty path gives "".
  std::string to_string() const;

  friend bool operator==(const PathType&, const PathType&) = default;
};

}  // namespace emlt

template <>
struct std::hash<emlt::PathType> {
  size_t operator()(const emlt::PathType& t) const noexcept {
    return std::hash<uint64_t>()(t.specular_mask * 0x9e3779b97f4a7c15ull ^ t.vertices);
  }
};
