#pragma once
// Helpers shared by the MLT strategy tests (perturbations, geometry-aware perturbations):
// shipped scenes at small sizes, bootstrap paths, a BDPT reference, an MLT image with a
// given mix, and the tile-wise convergence check.
#include <memory>
#include <string>
#include <vector>

#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/mcmc/mutation.h"
#include "emlt/path/path.h"
#include "emlt/run/integrator.h"
#include "emlt/scene/scene.h"

namespace emlt::test {

// scenes/<name>/scene.json at size x size pixels.
std::unique_ptr<Scene> shipped_scene(const std::string& name, int size);
// Up to `count` bootstrap paths of 3..max_edges segments that carry light.
std::vector<Path> bootstrap_paths(const Scene& scene, int count, int max_edges);
// Renders without a progress bar.
Image render(const Integrator& integrator, const Scene& scene, RenderSettings settings);
// Depth 6, 2 threads, seed 7: the settings every strategy test renders with.
RenderSettings base_settings();
Image bdpt_reference(const Scene& scene, int spp);
// The geometry-aware strategies' variants: the cheap cones (RenderSettings::gamlt_field_cone),
// the cells' size (0: the exact walk) and delayed acceptance
// (RenderSettings::gamlt_delayed_acceptance); the engine's defaults unless told.
struct GamltVariant {
  bool field_cone = false;
  double cone_cells = RenderSettings::kGamltConeCell;  // RenderSettings::gamlt_cone_cells
  bool delayed_acceptance = false;
};
// MLT with `mix` (64 chains, 50k bootstrap samples, 256-spp direct image).
Image mlt_image(const Scene& scene, const std::string& mix, double mpp,
                MltStatistics* stats = nullptr, GamltVariant variant = {});
// Luminance sums over blocks x blocks tiles and over the image. The image total must be
// within total_tolerance of the reference (it carries the bootstrap's error in b, a global
// scale), and each tile, divided by that total ratio, within tile_tolerance: the shape of
// the image, which is what a wrong proposal density distorts.
void expect_converged_to(const Image& image, const Image& reference, int blocks,
                         double tile_tolerance, double total_tolerance);
// The figures expect_converged_to checks: the image total over the reference's, and the
// worst tile's relative deviation after dividing by that ratio.
struct TileDeviation {
  double scale = 1.0;
  double worst = 0.0;
};
TileDeviation tile_deviation(const Image& image, const Image& reference, int blocks);
// The L D E path from the centre of a small downward-facing light above the origin to the
// floor point seen through `raster` (density tests on toy floors).
Path light_floor_eye_path(const Scene& scene, const Vec2& raster);
// The L D S D E path of a floor-mirror-light scene: the floor point seen through `raster`,
// the mirror hit from it along `up`, the floor point lit after the reflection, and the
// light straight above that.
Path floor_mirror_light_path(const Scene& scene, const Vec2& raster, const Vec3& up);
// The path of surface hits `hits` (light first), ending at the lens point `lens` seen through
// `raster`; the vertex `mirror` is a Dirac reflection (its record filled), the rest are what
// make_surface_vertex makes; type and densities computed.
Path path_through_mirror(const Scene& scene, const std::vector<SurfaceHit>& hits, const Vec3& lens,
                         const Vec2& raster, int mirror);
// The strategies report densities over the path layer's measure ν, which gives the mirror
// chain x3 -> x2 -> x1 the product of its segments' solid-angle-to-area factors, while the
// histograms measure area on the floor, where a direction at x3 reaches x1 at the distance
// of x3's mirror image: per unit solid angle dν = d32² d21² / (cos2 cos1) and
// dA(x1) = (d32 + d21)² / cos1. Returns log[(d32 + d21)² cos2 / (d32 d21)²], the factor
// that converts the reported ratios to floor area as the tests use it.
double log_floor_area_per_nu(const Path& path);
// Proposals from x whose vertex `moved` lands within `radius` of `target`, per proposal and
// unit area: a histogram estimate of T(x -> .) at target in area measure. Expects enough
// landings (> 800) for an estimate; `hits` (optional) receives their count.
double landing_density(const Mutation& mutation, const Path& x, int moved, const Vec3& target,
                       float radius, int proposals, const MutationContext& ctx, uint64_t seed,
                       int* hits = nullptr);
// The fraction of all proposals that were accepted moves of strategy `name`.
double share_of(const MltStatistics& stats, const std::string& name);

}  // namespace emlt::test
