#include "emlt/film/splat_film.h"

namespace emlt {

SplatFilm::SplatFilm(int width, int height, int extra_layers)
    : sums_(size_t(width) * size_t(height), DVec3(0.0)),
      layers_(size_t(std::max(extra_layers, 0)), std::vector<DVec3>(sums_.size(), DVec3(0.0))) {}

void SplatFilm::add_in_order(std::span<const SplatList> lists) {
  for (const SplatList& list : lists) {
    for (const SplatRecord& r : list.records) {
      sums_[r.pixel] += DVec3(r.value);
      if (r.layer >= 0 && r.layer < int(layers_.size()))
        layers_[size_t(r.layer)][r.pixel] += DVec3(r.value);
    }
  }
}

void SplatFilm::save(StateWriter& out) const {
  out.put_vector(sums_);
  for (const auto& layer : layers_) out.put_vector(layer);
}

void SplatFilm::load(StateReader& in) {
  sums_ = in.get_vector<DVec3>(sums_.size());
  for (auto& layer : layers_) layer = in.get_vector<DVec3>(sums_.size());
}

}  // namespace emlt
