#pragma once
// Helpers shared by the MLT strategy tests (perturbations, geometry-aware perturbations):
// shipped scenes at small sizes, bootstrap paths, a BDPT reference, an MLT image with a
// given mix, and the tile-wise convergence check.
#include <memory>
#include <string>
#include <vector>

#include "emlt/mcmc/mlt_integrator.h"
#include "emlt/mcmc/mutation.h"
#include "emlt/path/path.h"
#include "emlt/render/integrator.h"
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
// MLT with `mix` (64 chains, 50k bootstrap samples, 256-spp direct image).
Image mlt_image(const Scene& scene, const std::string& mix, double mpp, MltStatistics* stats = nullptr);
// Luminance sums over blocks x blocks tiles and over the image. The image total must be
// within total_tolerance of the reference (it carries the bootstrap's error in b, a global
// scale), and each tile, divided by that total ratio, within tile_tolerance: the shape of
// the image, which is what a wrong proposal density distorts.
void expect_converged_to(const Image& image, const Image& reference, int blocks, double tile_tolerance,
                         double total_tolerance);
// The L D E path from the centre of a small downward-facing light above the origin to the
// floor point seen through `raster` (density tests on toy floors).
Path light_floor_eye_path(const Scene& scene, const Vec2& raster);
// Proposals from x whose vertex `moved` lands within `radius` of `target`, per proposal and
// unit area: a histogram estimate of T(x -> .) at target in area measure. Expects enough
// landings (> 800) for an estimate; `hits` (optional) receives their count.
double landing_density(const Mutation& mutation, const Path& x, int moved, const Vec3& target,
                       float radius, int proposals, const MutationContext& ctx, uint64_t seed,
                       int* hits = nullptr);
// The fraction of all proposals that were accepted moves of strategy `name`.
double share_of(const MltStatistics& stats, const std::string& name);

}  // namespace emlt::test
