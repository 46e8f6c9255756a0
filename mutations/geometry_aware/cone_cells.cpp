#include "mutations/geometry_aware/cone_cells.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>

#include "mutations/geometry_aware/cone.h"

namespace emlt::geometry_aware {

namespace {

enum EndKind : int32_t { kPlane = 1, kSphere = 2, kCamera = 3 };

// Normals rounded to 2^-16: the canonical end then lies off the real plane by at most
// 2^-16 √3 times its distance from the real end (a cell's diagonal), far inside the walk's
// own-surface tolerance (2e-4 of the coordinates' size), so the end's wall is still left out.
constexpr double kNormalStep = 1.0 / 65536.0;
// Plane offsets rounded to E 2^-20, also far inside that tolerance.
constexpr double kOffsetStep = 1.0 / 1048576.0;
// Cells further than this from the scene's box are not quantised (int64 room, and such a
// segment is the environment's business anyway).
constexpr double kFarthestCell = 1e15;
constexpr int kDeepestLevel = 40;

struct Grid {
  DVec3 origin{0.0};
  double extent = 0.0;  // E, the box's longest side
  const std::vector<SurfaceBvh::Sphere>* spheres = nullptr;
};

bool grid_of(const Scene& scene, Grid* grid) {
  const SurfaceBvh& bvh = scene.surface_bvh();
  if (bvh.triangle_count() == 0) return false;
  const DVec3 lower(bvh.lower()), upper(bvh.upper());
  const DVec3 size = upper - lower;
  grid->origin = lower;
  grid->extent = std::max({size.x, size.y, size.z});
  grid->spheres = &bvh.spheres();
  return grid->extent > 0.0 && std::isfinite(grid->extent);
}

// Exact binary arithmetic on the doubles' bits, not the library's log2, ldexp, floor and
// lround (calls on the baseline x86-64: with them a key cost about 1,160 instructions, without
// about 380). The logarithms and powers are for positive normal doubles, which the callers
// ensure; the roundings for any value well inside int64's range.
int exponent_of(double x) {
  return int((std::bit_cast<uint64_t>(x) >> 52) & 0x7ff) - 1023;
}
double mantissa_of(double x) {  // in [1, 2)
  return std::bit_cast<double>((std::bit_cast<uint64_t>(x) & ((uint64_t(1) << 52) - 1)) |
                               std::bit_cast<uint64_t>(1.0));
}
double power_of_two(int k) {
  return std::bit_cast<double>(uint64_t(k + 1023) << 52);
}
// ⌈log2 x⌉.
int ceil_log2(double x) {
  return exponent_of(x) + (mantissa_of(x) > 1.0 ? 1 : 0);
}
// 2^(q / 4) for q = 0..3, rounded: the limits' steps.
constexpr double kQuarterPowers[4] = {1.0, 1.189207115002721, 1.4142135623730951,
                                      1.681792830507429};
double limit_angle(int32_t limit) {
  const int32_t whole = limit >= 0 ? limit / 4 : -((-limit + 3) / 4);
  return power_of_two(whole) * kQuarterPowers[limit - 4 * whole];
}
// The largest q with limit_angle(q) ≤ x, and the smallest with limit_angle(q) ≥ x.
int32_t floor_quarter_log2(double x) {
  const double m = mantissa_of(x);
  return 4 * exponent_of(x) + (m >= kQuarterPowers[1]) + (m >= kQuarterPowers[2]) +
         (m >= kQuarterPowers[3]);
}
int32_t ceil_quarter_log2(double x) {
  const int32_t q = floor_quarter_log2(x);
  return limit_angle(q) == x ? q : q + 1;
}
int64_t floor_to_int(double x) {
  const int64_t i = int64_t(x);
  return i - (double(i) > x ? 1 : 0);
}
int64_t round_to_int(double x) {
  return floor_to_int(x + 0.5);
}

double cell_size(const Grid& grid, int level) {
  return grid.extent * power_of_two(-level);
}

DVec3 cell_centre(const Grid& grid, int level, const int64_t cell[3]) {
  const double h = cell_size(grid, level);
  const DVec3 index{static_cast<double>(cell[0]), static_cast<double>(cell[1]),
                    static_cast<double>(cell[2])};
  return grid.origin + (index + 0.5) * h;
}

// The analytic sphere whose surface holds p, by the walk's own-surface tolerance, or −1.
int sphere_holding(const Grid& grid, const Vec3& p) {
  const auto& spheres = *grid.spheres;
  if (spheres.empty()) return -1;
  const float scale = std::max({1.0f, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  for (size_t i = 0; i < spheres.size(); ++i)
    if (std::abs(glm::length(p - spheres[i].center) - spheres[i].radius) < 2e-4f * scale)
      return int(i);
  return -1;
}

bool end_key(const Grid& grid, int level, const PathVertex& v, CellKey::End* end) {
  if (v.is_camera()) {
    end->kind = kCamera;
    for (int i = 0; i < 3; ++i) end->surface[i] = std::bit_cast<int32_t>(v.position[i]);
    return true;
  }
  const DVec3 p(v.position);
  const DVec3 cell = (p - grid.origin) * (1.0 / cell_size(grid, level));
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(cell[i]) < kFarthestCell)) return false;
    end->cell[i] = floor_to_int(cell[i]);
  }
  if (const int sphere = sphere_holding(grid, v.position); sphere >= 0) {
    end->kind = kSphere;
    end->surface[0] = sphere;
    return true;
  }
  const DVec3 normal(v.normal);
  const double length = glm::length(normal);
  if (!(length > 0.0) || !std::isfinite(length)) return false;
  end->kind = kPlane;
  DVec3 rounded;
  for (int i = 0; i < 3; ++i) {
    end->surface[i] = int32_t(round_to_int(normal[i] / (length * kNormalStep)));
    rounded[i] = double(end->surface[i]);
  }
  const double offset = glm::dot(rounded / glm::length(rounded), p) / (grid.extent * kOffsetStep);
  if (!(std::abs(offset) < kFarthestCell)) return false;
  end->offset = round_to_int(offset);
  return true;
}

bool key_of(const Grid& grid, const PathVertex& apex, const PathVertex& other, double fraction,
            CellKey* key) {
  if (apex.is_environment() || other.is_environment() || !(fraction > 0.0)) return false;
  const double length = glm::length(DVec3(other.position) - DVec3(apex.position));
  const double ratio = grid.extent / (fraction * length);
  if (!(ratio < 1e300) || !(ratio > 0.0)) return false;  // a zero or non-finite length
  // The coarsest level whose cells are at most f L wide.
  const int level = std::clamp(ratio >= 1e-300 ? ceil_log2(ratio) : 0, 0, kDeepestLevel);
  *key = CellKey{};
  key->level = level;
  return end_key(grid, level, apex, &key->ends[0]) && end_key(grid, level, other, &key->ends[1]);
}

// The key's canonical end: its cell's centre on its surface.
PathVertex canonical_end(const Grid& grid, int level, const CellKey::End& end) {
  PathVertex v;
  v.kind = VertexKind::Surface;
  if (end.kind == kCamera) {
    v.kind = VertexKind::Camera;
    for (int i = 0; i < 3; ++i) v.position[i] = std::bit_cast<float>(end.surface[i]);
    return v;
  }
  const DVec3 centre = cell_centre(grid, level, end.cell);
  DVec3 point = centre;
  if (end.kind == kSphere) {
    const SurfaceBvh::Sphere& sphere = (*grid.spheres)[size_t(end.surface[0])];
    const DVec3 from_centre = centre - DVec3(sphere.center);
    const double distance = glm::length(from_centre);
    const DVec3 direction = distance > 0.0 ? from_centre / distance : DVec3(0.0, 0.0, 1.0);
    point = DVec3(sphere.center) + double(sphere.radius) * direction;
  } else {
    DVec3 normal{static_cast<double>(end.surface[0]), static_cast<double>(end.surface[1]),
                 static_cast<double>(end.surface[2])};
    normal /= glm::length(normal);
    const double offset = double(end.offset) * grid.extent * kOffsetStep;
    point = centre - (glm::dot(normal, centre) - offset) * normal;
  }
  v.position = Vec3(point);
  return v;
}

uint64_t mix(uint64_t h, uint64_t value) {
  return (h ^ value) * 0xff51afd7ed558ccdull;
}

uint64_t hash(const CellKey& key) {
  uint64_t h = mix(0x9E3779B97F4A7C15ull, uint32_t(key.level));
  for (const CellKey::End& end : key.ends) {
    h = mix(h, uint64_t(uint32_t(end.kind)) << 32 | uint32_t(end.surface[0]));
    h = mix(h, uint64_t(uint32_t(end.surface[1])) << 32 | uint32_t(end.surface[2]));
    h = mix(h, uint64_t(end.offset));
    for (const int64_t c : end.cell) h = mix(h, uint64_t(c));
  }
  return h ^ (h >> 29);
}

// Whether limits are usable, and the rounded limits a cone is computed over: powers of
// 2^(1/4) at least a trillionth below alpha_min and above alpha_max, so that the walk's bounds
// decide the clamp to alpha_min and alpha_max even after rounding (see serves).
bool limits_usable(double alpha_min, double alpha_max) {
  return alpha_min >= 1e-300 && alpha_max >= alpha_min && alpha_max < 1e300;
}
double rounded_min(double alpha_min) {
  return limit_angle(floor_quarter_log2(alpha_min * (1.0 - 1e-12)));
}
double rounded_max(double alpha_max) {
  return limit_angle(ceil_quarter_log2(alpha_max * (1.0 + 1e-12)));
}

// The walk over the key's canonical segment between lo and hi (estimate_cone_tan).
ConeTan key_cone(const Scene& scene, const Grid& grid, const CellKey& key, double lo, double hi) {
  const PathVertex apex = canonical_end(grid, key.level, key.ends[0]);
  const PathVertex other = canonical_end(grid, key.level, key.ends[1]);
  return estimate_cone_tan(scene, apex, other, lo, hi);
}

// The cone under the caller's limits from the walk's result, as estimate_cone_half_angle
// gives it from the same walk.
double cone_of(const ConeTan& cone, double alpha_min, double alpha_max) {
  if (!(cone.t > cone.tan_min)) return alpha_min;
  return std::clamp(std::atan(cone.t), alpha_min, alpha_max);
}

struct Entry {
  const Scene* scene = nullptr;
  CellKey key;
  ConeTan cone{0.0, 0.0, 0.0};
  double lo = 0.0, hi = 0.0;  // the rounded limits it was computed over
};

// Whether the entry gives what a walk under the caller's rounded limits would: always under
// the same limits (the same walk); under others when its t lies strictly between its bounds,
// since t is then tan α* itself and a walk under any limits gives the same clamp (where that
// walk stops at its floor or finds nothing below its ceiling, α* lies beyond the rounded
// limit, hence beyond the caller's: the trillionth keeps atan's rounding on the right side).
// An entry at its ceiling (nothing found below hi: α* ≥ hi) also serves any ceiling up to
// its own, and one at its floor (α* ≤ lo) any floor from its own up: a walk under such limits
// ends at the same bound, and the caller's clamp gives the same bits. Without these two, a
// key whose cone lies beyond its step range's clamp was walked again for every other rounded
// limit its segments asked for (on Veach Ajar at cells of 1/1, 232,000 of 283,000 walks).
// The limits are not in the key, so segments whose step ranges clamp their cones differently
// share an entry (the caustic move's second cone gets its limits from the first).
bool serves(const Entry& e, double lo, double hi) {
  const bool at_floor = !(e.cone.t > e.cone.tan_min), at_ceiling = !(e.cone.t < e.cone.tan_max);
  return (e.lo == lo && e.hi == hi) || (!at_floor && !at_ceiling) ||
         (at_ceiling && !at_floor && hi <= e.hi) || (at_floor && lo >= e.lo);
}

// This thread's table: 65,536 entries of 152 bytes (10 MB) in sets of four ways, each set's
// tags and last uses in 32 bytes of their own, so that a lookup reads one small line before
// comparing a whole key; a way is replaced when least recently used. The chains visit their
// states once per sweep (a sweep per power of two in mutations per pixel), so the keys of a
// chain's region come back after every other chain's: on Veach Ajar at 384x256, 16 mutations
// per pixel, cells of 1/2, a direct-mapped table of 16,384 entries walked 266,000 times for
// 58,000 distinct keys in 1.43 million lookups, this one 75,000. A way holds one key, so a
// hit returns exactly what a recomputation would (the key is compared whole).
struct Table {
  static constexpr size_t kSize = 65536, kWays = 4, kSets = kSize / kWays;
  struct Set {
    uint32_t tag[kWays] = {};
    uint32_t used[kWays] = {};
  };
  uint32_t clock = 0;  // counts lookups (wrapping after 2^32 only blurs which way is oldest)
  std::array<Set, kSets> sets;
  std::array<Entry, kSize> entries;
  // The grid of the scene last seen (Scene::surface_bvh is a call_once on every call).
  const Scene* scene = nullptr;
  bool has_grid = false;
  Grid grid;
};

thread_local CellConeCounts counts;
}  // namespace

CellConeCounts cell_cone_counts() {
  return counts;
}

bool cell_key(const Scene& scene, const PathVertex& apex, const PathVertex& other, double fraction,
              CellKey* key) {
  Grid grid;
  return grid_of(scene, &grid) && key_of(grid, apex, other, fraction, key);
}

double cell_key_cone(const Scene& scene, const CellKey& key, double alpha_min, double alpha_max) {
  Grid grid;
  grid_of(scene, &grid);
  return cone_of(key_cone(scene, grid, key, rounded_min(alpha_min), rounded_max(alpha_max)),
                 alpha_min, alpha_max);
}

double cell_cone_half_angle(const Scene& scene, const PathVertex& apex, const PathVertex& other,
                            double alpha_min, double alpha_max, double fraction,
                            CellConeBugs bugs) {
  thread_local std::unique_ptr<Table> table;
  if (!table) table = std::make_unique<Table>();
  if (table->scene != &scene) {
    table->scene = &scene;
    table->has_grid = grid_of(scene, &table->grid);
  }
  CellKey key;
  if (!table->has_grid || !limits_usable(alpha_min, alpha_max) ||
      !key_of(table->grid, apex, other, fraction, &key))
    return cone_half_angle(scene, apex, other, alpha_min, alpha_max);
  // The injected bug compares and hashes the key without the far end's cell: a slot filled
  // from another segment with the same apex is then taken for this one.
  CellKey lookup = key;
  if (bugs.key_without_other_cell)
    std::fill(std::begin(lookup.ends[1].cell), std::end(lookup.ends[1].cell), 0);
  ++counts.lookups;
  const double lo = rounded_min(alpha_min), hi = rounded_max(alpha_max);
  const uint64_t h = hash(lookup);
  const size_t set_index = h % Table::kSets;
  Table::Set& set = table->sets[set_index];
  Entry* ways = &table->entries[set_index * Table::kWays];
  const uint32_t tag = uint32_t(h >> 32) | 1u;  // 0: an empty way
  Entry* found = nullptr;
  size_t way = 0;
  for (; way < Table::kWays; ++way)
    if (set.tag[way] == tag && ways[way].scene == &scene && ways[way].key == lookup) {
      found = &ways[way];
      break;
    }
  const uint32_t now = ++table->clock;
  if (!found || !serves(*found, lo, hi)) {
    if (!found) {
      way = 0;
      for (size_t w = 1; w < Table::kWays; ++w)
        if (set.used[w] < set.used[way]) way = w;
      found = &ways[way];
      set.tag[way] = tag;
    }
    *found = {&scene, lookup, key_cone(scene, table->grid, key, lo, hi), lo, hi};
    ++counts.computed;
  }
  set.used[way] = now;
  return cone_of(found->cone, alpha_min, alpha_max);
}

}  // namespace emlt::geometry_aware
