#pragma once
// What the detailed-balance round trips (x -> y -> x') give a perturbation to take y back to
// x's positions: the quantities of x its move draws, read off x as the move itself reads them.
#include <vector>

#include "emlt/path/path.h"
#include "mutations/caustic_perturbation.h"
#include "mutations/multichain_perturbation.h"

namespace emlt::test {

// The caustic move's direction: out of its fixed vertex, towards the eye side.
inline Vec3 caustic_direction(const Path& x) {
  const int l = CausticPerturbation::fixed_vertex(x.type);
  return direction_between(x.vertices[size_t(l)], x.vertices[size_t(l + 1)]);
}

// The multi-chain move's directions at the interior non-specular vertices, from the eye.
inline std::vector<Vec3> multichain_directions(const Path& x) {
  const int l = MultiChainPerturbation::fixed_vertex(x.type);
  std::vector<Vec3> directions;
  for (int i = x.edges() - 1; i >= l + 2; --i)
    if (!x.vertices[size_t(i)].delta)
      directions.push_back(direction_between(x.vertices[size_t(i)], x.vertices[size_t(i - 1)]));
  return directions;
}

}  // namespace emlt::test
