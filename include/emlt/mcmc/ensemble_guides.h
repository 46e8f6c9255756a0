#pragma once
// The frozen complementary ensemble Y as EMLT's guided strategies see it (Bashford-Rogers et
// al. 2021, §3.1): Y's paths, the path-type tree over them, and the quantities derived from
// Y once per swap (the linear kernels' α, §3.4). A strategy asks for Υ, the guide paths of
// its current path's type: as the paper's §3.1.1 reads, by a counter (type, seed, chain,
// step), the same Υ both ways; or the M paths of that type nearest the
// current path's image point (along a Hilbert order of Y, path_type_index.h), a function of
// the path, so that the reverse move is evaluated against the proposal's own Υ.
// docs/emlt-fidelity.md gives the measurements that keep the counter as the default.
#include <cstdint>
#include <span>
#include <vector>

#include "emlt/mcmc/path_type_index.h"
#include "emlt/path/path.h"

namespace emlt {

// How a step's Υ is chosen (--ensemble-guides).
enum class GuideSelection {
  Nearby,   // the M paths of the type centred on the current path's image point
  Counter,  // M consecutive paths of the type from an offset hashed from (seed, chain, step)
};
// What the adaptive α of §3.4 is computed from (--ensemble-alpha-from).
enum class AlphaSource {
  Upsilon,   // the image points of the step's Υ (so α varies from step to step)
  Ensemble,  // the image points of all of Y (one α per swap)
};

struct EnsembleParams {
  // M, the size of Υ (--ensemble-neighbours). The paper gives no value. 8 and 32 give the
  // same error at equal mutations on the Cornell box and the door scene (within 7 %, seeds
  // 1-3), and a step with 8 costs 16 % less (1.22 against 1.45 µs).
  int neighbours = 8;
  // Length (scene units) that divides distances in the similarity of eq. 8 (1: the paper's
  // literal form); 0: the scene's bounding radius over sqrt(3), which is 1 on the paper's own
  // Cornell box (a cube of side 2) and keeps eq. 8 in that regime whatever a scene's units.
  double similarity_length = 0.0;
  // The adaptive α of the linear kernels (§3.4); false keeps alpha_fixed.
  bool adaptive_alpha = true;
  double alpha_fixed = 0.5;
  GuideSelection selection = GuideSelection::Counter;
  // The anisotropic path perturbation's covariance: eq. 11 as printed (1/(M-1) sum w (v-mu)^2,
  // normalised weights, no further factor), or the reliability-weighted covariance times the
  // strategy's own factor (AnisotropicPathParams: 0.05, measured on one scene).
  bool aniso_printed_covariance = true;
  // > 0: the factor on those covariances instead of the form's own (1 printed, 0.05 weighted).
  double aniso_covariance_scale = 0.0;
  // < 1: the anisotropic path perturbation's plane Gaussians (image and world) become scale
  // mixtures over [aniso_smallest_scale, 1], log-uniform (kernels.h, TangentGaussian), so the
  // fitted shape is tried at small scales too; 1: the paper's single Gaussian. Not in the
  // paper: with Υ drawn by the counter the fitted Σ spans a good part of the scene, and a chain
  // on a narrow peak of f rejects every such step (see docs/emlt-fidelity.md).
  double aniso_smallest_scale = 1.0;
  AlphaSource alpha_source = AlphaSource::Upsilon;
  // The anisotropic path perturbation falls back to an isotropic Gaussian on the tangent
  // plane instead of its vMF (RenderSettings::ensemble_plane_fallback).
  bool plane_fallback = false;
};

// Υ as the guided strategies read it: the guide paths, and the vertex data that the
// similarity weights and the kernels' fits read from every guide, stored contiguously.
// Reading those from the paths themselves costs a cache miss per guide (the paths of Y lie
// scattered in memory), which dominated a guided step. Guide n is entry n of every span.
class GuideView {
 public:
  size_t size() const { return paths_.size(); }
  bool empty() const { return paths_.empty(); }
  const Path* operator[](size_t n) const { return paths_[n]; }
  std::span<const Path* const> paths() const { return paths_; }
  // Each guide's raster() (where it lands on the film).
  std::span<const Vec2> rasters() const { return {rasters_, size()}; }
  // vertices[i].position of every guide, one coordinate (axis 0, 1, 2 = x, y, z) per array,
  // converted to double (exactly): the layout in which the similarity of one point to every
  // guide vectorises. i < the type's vertex count.
  std::span<const double> coordinates(int i, int axis) const {
    return {coordinates_ + (3 * size_t(i) + size_t(axis)) * stride_, size()};
  }
  // vertices[i].position of guide n.
  Vec3 position(size_t n, int i) const {
    return Vec3(float(coordinates(i, 0)[n]), float(coordinates(i, 1)[n]),
                float(coordinates(i, 2)[n]));
  }
  // Whether any guide has an environment vertex. When not, sky_directions() and
  // environment() are empty, and a guide's sky_direction must be read from its path.
  bool has_environment() const { return sky_directions_ != nullptr; }
  std::span<const Vec3> sky_directions(int i) const {
    return has_environment() ? std::span<const Vec3>(sky_directions_ + size_t(i) * stride_, size())
                             : std::span<const Vec3>();
  }
  // vertices[i].is_environment() of every guide, as 0 / 1.
  std::span<const uint8_t> environment(int i) const {
    return has_environment() ? std::span<const uint8_t>(environment_ + size_t(i) * stride_, size())
                             : std::span<const uint8_t>();
  }
  // Whether every guide's vertex i is the same surface point (a pinhole camera's lens
  // point): then a vertex has one similarity to all of them, computed once.
  bool same_point(int i) const { return same_point_ && same_point_[i]; }
  // The linear kernels' α for a step guided by this Υ (§3.4).
  double alpha() const { return alpha_; }
  // Whether both views are the same window of the same swap's Υ.
  bool same_as(const GuideView& other) const {
    return origin_ == other.origin_ && size() == other.size() &&
           paths_.data() == other.paths_.data();
  }
  // Guide n of another view of the same swap's Υ (the reverse move's), as an index of this
  // view; -1 when this view does not hold it (then the reverse move cannot choose it).
  long index_of(const GuideView& other, size_t n) const {
    const long i = long(other.origin_ + n) - long(origin_);
    return i >= 0 && size_t(i) < size() ? i : -1;
  }

 private:
  friend class EnsembleGuides;

  std::span<const Path* const> paths_;
  const Vec2* rasters_ = nullptr;
  const double* coordinates_ = nullptr;   // row (i, axis) starts at (3 i + axis) * stride_
  const Vec3* sky_directions_ = nullptr;  // row i starts at i * stride_
  const uint8_t* environment_ = nullptr;  // likewise
  const uint8_t* same_point_ = nullptr;   // one entry per vertex
  size_t stride_ = 0;
  size_t origin_ = 0;  // the first guide's entry in the swap's layout (guides' identity)
  double alpha_ = 0.5;
};

class EnsembleGuides {
 public:
  // Rebuilds from Y (null paths, chains without a seed, are left out). `seed` keys the
  // deterministic choice of Υ.
  void build(std::span<const Path* const> paths, int width, int height, uint64_t seed,
             const EnsembleParams& params);

  // Υ of a path at this chain's step, by params().selection: up to M paths of Y of the
  // same type. The view stays valid until the next build().
  GuideView upsilon(const Path& path, uint64_t chain, uint64_t step) const;
  // Υ chosen by the counter, whatever params().selection says: for the strategies whose
  // density needs the same Υ in both directions.
  GuideView counter_upsilon(const PathType& type, uint64_t chain, uint64_t step) const;
  // Υ near an image point (GuideSelection::Nearby).
  GuideView nearby_upsilon(const PathType& type, const Vec2& raster) const;

  const EnsembleParams& params() const { return params_; }
  // α of all of Y (AlphaSource::Ensemble), or the fixed α.
  double alpha() const { return alpha_; }
  size_t size() const { return paths_.size(); }

 private:
  // A type's members and their vertex data, in the index's member order and extended
  // cyclically by its first entries, so that every Υ (M consecutive members, cyclically) is
  // one contiguous range of each array.
  struct Block {
    size_t first = 0;            // of the block's entries in guide_paths_ and rasters_
    size_t stride = 0;           // entries per row: members + extension
    size_t vertex_data = 0;      // offset of the block's rows in coordinates_, in units of 3 rows
    size_t sky_data = 0;         // offset of the block's rows in sky_directions_ / environment_
    size_t same_point_data = 0;  // offset of the block's entries in same_point_
    bool has_environment = false;
  };

  std::vector<const Path*> paths_;
  PathTypeIndex index_;
  EnsembleParams params_;
  uint64_t seed_ = 0;
  double alpha_ = 0.5;
  std::vector<Block> blocks_;  // one per group of index_
  std::vector<const Path*> guide_paths_;
  std::vector<Vec2> rasters_;
  std::vector<double> coordinates_;
  std::vector<Vec3> sky_directions_;
  std::vector<uint8_t> environment_;
  std::vector<uint8_t> same_point_;  // per block and vertex: GuideView::same_point
  std::vector<double> window_alpha_;  // per entry s: α of the Υ that starts there

  GuideView view(const PathTypeIndex::Window& window) const;
};

}  // namespace emlt
