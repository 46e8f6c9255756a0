#include "emlt/mcmc/ensemble_guides.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cassert>

#include "emlt/mcmc/adaptive_alpha.h"

namespace emlt {

void EnsembleGuides::build(std::span<const Path* const> paths, int width, int height, uint64_t seed,
                           const EnsembleParams& params) {
  params_ = params;
  seed_ = seed;
  paths_.clear();
  std::vector<PathType> types;
  types.reserve(paths.size());
  for (const Path* p : paths)
    if (p && !p->vertices.empty()) {
      paths_.push_back(p);
      types.push_back(p->type);
    }
  index_.build(types);
  const bool nearby = params_.selection == GuideSelection::Nearby;
  std::vector<Vec2> raster(paths_.size());
  if (nearby) {
    // The type lists in Hilbert order of the paths' image points, before the layout below
    // copies them in list order.
    tbb::parallel_for(size_t(0), paths_.size(), [&](size_t i) { raster[i] = paths_[i]->raster(); });
    index_.order_by_raster(raster, width, height);
  }

  // Lay out the blocks: an Υ of up to M entries starting anywhere in a list of `size`
  // needs min(M, size) - 1 entries repeated past its end.
  const size_t m = params_.neighbours > 0 ? size_t(params_.neighbours) : 0;
  blocks_.assign(index_.type_count(), Block{});
  size_t entries = 0, vertex_entries = 0;
  for (size_t g = 0; g < blocks_.size(); ++g) {
    const size_t size = index_.group_members(g).size();
    Block& block = blocks_[g];
    block.first = entries;
    block.stride = size + std::min(m, size) - (m > 0 ? 1 : 0);
    block.vertex_data = vertex_entries;
    entries += block.stride;
    vertex_entries += block.stride * index_.group_type(g).vertices;
  }
  guide_paths_.resize(entries);
  rasters_.resize(entries);
  coordinates_.resize(3 * vertex_entries);

  // Each path is read once per swap (instead of once per guided step that draws it as a
  // guide). The reads are scattered, so the paths a few entries ahead are prefetched; the
  // writes are in order. In parallel over chunks of each type's entries, each entry written
  // by one task: the layout is the same on any thread count. (Built serially, the other
  // threads waited through every swap, and the paper's schedule swaps every few steps per
  // path: 16 threads ran EMLT 10 % slower.)
  constexpr size_t kChunk = 1024;
  tbb::parallel_for(size_t(0), blocks_.size(), [&](size_t g) {
    Block& block = blocks_[g];
    const std::span<const uint32_t> members = index_.group_members(g);
    const size_t vertices = index_.group_type(g).vertices;
    tbb::parallel_for(size_t(0), (block.stride + kChunk - 1) / kChunk, [&](size_t chunk) {
      const size_t begin = chunk * kChunk, end = std::min(block.stride, begin + kChunk);
      bool environment = false;
      for (size_t k = begin; k < end; ++k) {
        if (k + 16 < members.size()) __builtin_prefetch(paths_[members[k + 16]]);
        if (k + 8 < members.size()) {
          const Path* ahead = paths_[members[k + 8]];
          for (const PathVertex& v : ahead->vertices) __builtin_prefetch(&v);
          // The raster, at the end of the last vertex, usually lies on a line of its own.
          __builtin_prefetch(&ahead->vertices.back().raster);
        }
        const uint32_t member = members[k % members.size()];
        const Path* path = paths_[member];
        assert(path->vertices.size() == vertices);
        for (size_t i = 0; i < vertices; ++i) {
          const PathVertex& v = path->vertices[i];
          for (size_t axis = 0; axis < 3; ++axis)
            coordinates_[3 * block.vertex_data + (3 * i + axis) * block.stride + k] =
                v.position[int(axis)];
          environment |= v.is_environment();
        }
        guide_paths_[block.first + k] = path;
        rasters_[block.first + k] = path->raster();  // the last vertex, just read
        // The entries past the members repeat them: one write per member.
        if (k < members.size()) raster[member] = rasters_[block.first + k];
      }
      if (environment)
        std::atomic_ref<bool>(block.has_environment).store(true, std::memory_order_relaxed);
    });
  });
  // The vertices at which every guide of a type is the same point (no sky vertex): a
  // pinhole camera's lens point, in every guided lens perturbation's similarity.
  same_point_.clear();
  for (size_t g = 0; g < blocks_.size(); ++g) {
    Block& block = blocks_[g];
    block.same_point_data = same_point_.size();
    for (size_t i = 0; i < index_.group_type(g).vertices; ++i) {
      bool same = !block.has_environment;
      for (size_t axis = 0; axis < 3 && same; ++axis) {
        const double* row = &coordinates_[3 * block.vertex_data + (3 * i + axis) * block.stride];
        same = std::all_of(row, row + block.stride, [&](double c) { return c == row[0]; });
      }
      same_point_.push_back(uint8_t(same));
    }
  }
  alpha_ = params.adaptive_alpha
               ? ensemble::adaptive_alpha(ensemble::image_coverage(raster, width, height))
               : params.alpha_fixed;
  // α of every Υ a step can be given: the window of min(M, size) entries starting at each
  // entry of a type's list (§3.4 applied to Υ's image points). In parallel over chunks of
  // each type's entries, as the layout: the paper's schedule swaps every few steps per path.
  window_alpha_.assign(entries, alpha_);
  if (params.adaptive_alpha && params.alpha_source == AlphaSource::Upsilon)
    tbb::parallel_for(size_t(0), blocks_.size(), [&](size_t g) {
      const Block& block = blocks_[g];
      const size_t size = index_.group_members(g).size(), count = std::min(m, size);
      tbb::parallel_for(size_t(0), (size + kChunk - 1) / kChunk, [&](size_t chunk) {
        for (size_t s = chunk * kChunk; s < std::min(size, (chunk + 1) * kChunk); ++s)
          window_alpha_[block.first + s] = ensemble::adaptive_alpha(ensemble::image_coverage(
              std::span<const Vec2>(rasters_.data() + block.first + s, count), width, height));
      });
    });

  // Sky directions only for the types that have an environment vertex (none in most scenes).
  size_t sky_entries = 0;
  for (size_t g = 0; g < blocks_.size(); ++g) {
    Block& block = blocks_[g];
    block.sky_data = sky_entries;
    if (block.has_environment) sky_entries += block.stride * index_.group_type(g).vertices;
  }
  sky_directions_.resize(sky_entries);
  environment_.resize(sky_entries);
  for (size_t g = 0; g < blocks_.size(); ++g) {
    const Block& block = blocks_[g];
    if (!block.has_environment) continue;
    for (size_t k = 0; k < block.stride; ++k) {
      const Path* path = guide_paths_[block.first + k];
      for (size_t i = 0; i < index_.group_type(g).vertices; ++i) {
        const PathVertex& v = path->vertices[i];
        sky_directions_[block.sky_data + i * block.stride + k] = v.sky_direction;
        environment_[block.sky_data + i * block.stride + k] = uint8_t(v.is_environment());
      }
    }
  }
}

GuideView EnsembleGuides::upsilon(const Path& path, uint64_t chain, uint64_t step) const {
  return params_.selection == GuideSelection::Nearby ? nearby_upsilon(path.type, path.raster())
                                                     : counter_upsilon(path.type, chain, step);
}

GuideView EnsembleGuides::counter_upsilon(const PathType& type, uint64_t chain,
                                          uint64_t step) const {
  return view(index_.window(type, seed_, chain, step, params_.neighbours));
}

GuideView EnsembleGuides::nearby_upsilon(const PathType& type, const Vec2& raster) const {
  return view(index_.nearby_window(type, raster, params_.neighbours));
}

GuideView EnsembleGuides::view(const PathTypeIndex::Window& window) const {
  GuideView view;
  if (window.count == 0) return view;
  const Block& block = blocks_[window.group];
  view.paths_ =
      std::span<const Path* const>(guide_paths_.data() + block.first + window.start, window.count);
  view.rasters_ = rasters_.data() + block.first + window.start;
  view.coordinates_ = coordinates_.data() + 3 * block.vertex_data + window.start;
  if (block.has_environment) {
    view.sky_directions_ = sky_directions_.data() + block.sky_data + window.start;
    view.environment_ = environment_.data() + block.sky_data + window.start;
  }
  view.same_point_ = same_point_.data() + block.same_point_data;
  view.stride_ = block.stride;
  view.origin_ = block.first + window.start;
  view.alpha_ = window_alpha_[block.first + window.start];
  return view;
}

}  // namespace emlt
